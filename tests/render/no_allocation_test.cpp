// The frame loop's per-frame work must not allocate (developers' guide:
// "the hot loop does no allocation"). This binary replaces the global
// operator new to count allocations while a frame's phases run.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "app/frame_recorder.h"
#include "render/cpu_renderers.h"
#include "scene/camera.h"
#include "test_support.h"

namespace {
std::atomic<long> gAllocations{0};
}

void* operator new(std::size_t size) {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// GCC 12 takes the replaced operator new for the standard one and warns
// that free() releases its memory; here new is malloc, so free is right.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace rt {
namespace {

// Every CPU renderer sizes its working buffer and scratch in prepare();
// oneTBB's own task storage does not go through operator new either. The
// recorder, like the frame loop's, was sized before the frames.
TEST(NoAllocation, FramePhasesOfEveryCpuRenderer) {
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    const auto kind = static_cast<RendererKind>(i);
    if (!cpuRendererBuilt(kind)) continue;
    for (const char* name : test::kSceneNames) {
      const Scene scene = test::loadNamedScene(name);
      for (const Stage stage : {Stage::original, Stage::single_pass, Stage::optimized}) {
        const auto renderer = makeCpuRenderer(kind);
        renderer->prepare(scene, {67, 29}, optionsForStage(stage));
        FrameRecorder recorder(4);
        const long before = gAllocations.load();
        for (long long k = 0; k < 4; ++k) {
          renderer->render(cameraAtFrame(scene.camera, k));
          renderer->present();
          FrameRecord record;
          record.frame = k;
          recorder.record(record);
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

}  // namespace
}  // namespace rt
