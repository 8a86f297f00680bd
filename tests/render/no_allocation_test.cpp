// The frame loop's per-frame work must not allocate (developers' guide:
// "the hot loop does no allocation"). This binary replaces the global
// operator new to count allocations while a frame's phases run.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>

#include "app/frame_recorder.h"
#include "render/cpu_renderers.h"
#include "scene/camera.h"
#include "test_support.h"

namespace {
std::atomic<long> gAllocations{0};

// Every replaceable allocation form below counts and takes its memory from
// malloc (aligned_alloc for the aligned forms), and every deallocation form
// gives it back with free, so whichever forms a library pairs, new and
// delete agree (under ASan too: malloc and free on both sides). Replacing
// only some forms is not enough: GoogleTest 1.16 allocates with the nothrow
// form, and the library's own nothrow new paired with the delete here is
// the mismatch ASan reports; the aligned forms serve over-aligned types
// (the Embree kernel's worker slots), whose allocations count as well.
void* allocate(std::size_t size) noexcept {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}

void* allocateAligned(std::size_t size, std::align_val_t alignment) noexcept {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  const auto align = static_cast<std::size_t>(alignment);
  // aligned_alloc takes a size that is a multiple of the alignment (C11
  // 7.22.3.1; ASan checks it).
  const std::size_t rounded = (std::max<std::size_t>(size, 1) + align - 1) / align * align;
  return std::aligned_alloc(align, rounded);
}

void* orThrow(void* p) {
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t size) { return orThrow(allocate(size)); }
void* operator new[](std::size_t size) { return orThrow(allocate(size)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new(std::size_t size, std::align_val_t alignment) { return orThrow(allocateAligned(size, alignment)); }
void* operator new[](std::size_t size, std::align_val_t alignment) { return orThrow(allocateAligned(size, alignment)); }
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return allocateAligned(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return allocateAligned(size, alignment);
}
// GCC takes the replaced operator new for the standard one and warns that
// free() releases its memory; here new is malloc, so free is right.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace rt {
namespace {

// Every CPU renderer sizes its working buffer and scratch in prepare();
// oneTBB's own task storage does not go through operator new either. The
// recorder, like the frame loop's with --counters, was sized before the frames.
TEST(NoAllocation, FramePhasesOfEveryCpuRenderer) {
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    const auto kind = static_cast<RendererKind>(i);
    if (!cpuRendererBuilt(kind)) continue;
    for (const char* name : test::kSceneNames) {
      const Scene scene = test::loadNamedScene(name);
      for (const Stage stage : {Stage::original, Stage::single_pass, Stage::optimized}) {
        const auto renderer = makeCpuRenderer(kind);
        renderer->prepare(scene, {67, 29}, optionsForStage(stage));
        FrameRecorder recorder(4, true);
        const long before = gAllocations.load();
        for (long long k = 0; k < 4; ++k) {
          renderer->render(cameraAtFrame(scene.camera, k));
          renderer->present();
          FrameRecord record;
          record.frame = k;
          recorder.record(record, renderer->lastCounters());
        }
        EXPECT_EQ(gAllocations.load() - before, 0) << nameOf(kind) << " " << name << " stage " << nameOf(stage);
      }
    }
  }
}

TEST(NoAllocation, CounterSeesAllocations) {
  const long before = gAllocations.load();
  auto p = std::make_unique<int>(3);
  EXPECT_GT(gAllocations.load() - before, 0);
}

// Allocations that allocate() makes, and each pointer handed to a volatile,
// so the compiler may not drop a new-expression with its delete.
template <typename Allocate>
long allocationsOf(Allocate allocate) {
  const long before = gAllocations.load();
  allocate();
  return gAllocations.load() - before;
}
void* volatile gSink = nullptr;

struct alignas(64) OverAligned {
  char bytes[64];
};

bool aligned(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % alignof(OverAligned) == 0; }

// Each form the counter replaces counts once, and the aligned ones align.
TEST(NoAllocation, CounterSeesEveryAllocationForm) {
  EXPECT_EQ(allocationsOf([] {
              int* p = new int(1);
              gSink = p;
              delete p;
            }),
            1);
  EXPECT_EQ(allocationsOf([] {
              int* p = new int[3];
              gSink = p;
              delete[] p;
            }),
            1);
  EXPECT_EQ(allocationsOf([] {
              int* p = new (std::nothrow) int(1);
              gSink = p;
              delete p;
            }),
            1);
  EXPECT_EQ(allocationsOf([] {
              int* p = new (std::nothrow) int[3];
              gSink = p;
              delete[] p;
            }),
            1);
  EXPECT_EQ(allocationsOf([] {
              auto* p = new OverAligned;
              EXPECT_TRUE(aligned(p));
              gSink = p;
              delete p;
            }),
            1);
  EXPECT_EQ(allocationsOf([] {
              auto* p = new OverAligned[3];
              EXPECT_TRUE(aligned(p));
              gSink = p;
              delete[] p;
            }),
            1);
  EXPECT_EQ(allocationsOf([] {
              auto* p = new (std::nothrow) OverAligned;
              EXPECT_TRUE(aligned(p));
              gSink = p;
              delete p;
            }),
            1);
  EXPECT_EQ(allocationsOf([] {
              auto* p = new (std::nothrow) OverAligned[3];
              EXPECT_TRUE(aligned(p));
              gSink = p;
              delete[] p;
            }),
            1);
}

}  // namespace
}  // namespace rt
