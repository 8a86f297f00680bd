// The frame loop's per-frame work must not allocate (developers' guide:
// "the hot loop does no allocation"). This binary replaces the global
// operator new to count allocations while a frame's phases run.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "app/frame_recorder.h"
#include "render/renderer_factory.h"
#include "render/sequential_renderer.h"
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
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace rt {
namespace {

TEST(NoAllocation, FramePhasesOfTheSequentialRenderer) {
  for (const char* name : test::kSceneNames) {
    const Scene scene = test::loadNamedScene(name);
    for (const Stage stage : {Stage::original, Stage::single_pass, Stage::optimized}) {
      SequentialRenderer renderer;
      const Extent extent{64, 48};
      renderer.prepare(scene, extent, optionsForStage(stage));
      FrameRecorder recorder(4);
      const long before = gAllocations.load();
      for (long long k = 0; k < 4; ++k) {
        const CameraFrame camera = cameraAtFrame(scene.camera, k);
        renderer.render(camera);
        renderer.present();
        FrameRecord record;
        record.frame = k;
        recorder.record(record);
      }
      EXPECT_EQ(gAllocations.load() - before, 0) << name << " stage " << nameOf(stage);
    }
  }
}

// The SIMD and oneTBB renderers size their scratch in prepare(); oneTBB's
// own task storage does not go through operator new either.
TEST(NoAllocation, FramePhasesOfTheParallelRenderers) {
  const Scene scene = test::loadNamedScene("random20");
  for (const RendererKind kind : {RendererKind::simd_tbb, RendererKind::simd_only, RendererKind::tbb_only}) {
    for (const Stage stage : {Stage::original, Stage::optimized}) {
      const auto renderer = makeRenderer(kind);
      const Extent extent{67, 29};
      renderer->prepare(scene, extent, optionsForStage(stage));
      const long before = gAllocations.load();
      for (long long k = 0; k < 4; ++k) {
        renderer->render(cameraAtFrame(scene.camera, k));
        renderer->present();
      }
      EXPECT_EQ(gAllocations.load() - before, 0) << nameOf(kind) << " stage " << nameOf(stage);
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
