// The threaded and SIMD renderers beyond image agreement: thread counts do
// not change a pixel, lanes follow the target, settings reach the CSV
// fields, and the scheduler hands out every pixel exactly once.
#include <gtest/gtest.h>

#include <atomic>
#include <type_traits>
#include <vector>

#include "render/render_test_support.h"
#include "render/renderer_factory.h"
#include "render/row_scheduler.h"
#include "render/sequential_renderer.h"
#include "render/simd/simd_renderer.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr Extent kOdd{101, 37};
constexpr long long kFrame = 30;

Image render(RendererKind kind, const ParallelSettings& settings, const Scene& scene, Extent extent,
             const RenderOptions& options) {
  // One renderer at a time: each holds a process-wide oneTBB thread limit.
  const auto renderer = makeRenderer(kind, settings);
  return test::renderFrame(*renderer, scene, extent, options, kFrame);
}

ParallelSettings threads(int n, Partition partition = Partition::rows, int grain = 1) {
  ParallelSettings s;
  s.threads = n;
  s.partition = partition;
  s.grain = grain;
  return s;
}

// Rows are independent, so how they are spread over threads must not
// change one bit, for any split.
TEST(Threads, OneAndManyThreadsGiveIdenticalImages) {
  const Scene scene = test::loadNamedScene("random100");
  for (const RendererKind kind : {RendererKind::simd_tbb, RendererKind::tbb_only}) {
    for (const Stage stage : {Stage::original, Stage::optimized}) {
      const RenderOptions options = optionsForStage(stage);
      const Image one = render(kind, threads(1), scene, kOdd, options);
      for (const Partition partition : {Partition::rows, Partition::tiles}) {
        for (const int grain : {1, 3}) {
          const Image many = render(kind, threads(4, partition, grain), scene, kOdd, options);
          EXPECT_TRUE(std::ranges::equal(one.pixels(), many.pixels()))
              << nameOf(kind) << " " << nameOf(stage) << " " << nameOf(partition) << " grain " << grain;
        }
      }
    }
  }
}

TEST(Threads, SimdTbbEqualsSimdOnlyAndTbbOnlyEqualsSequential) {
  const Scene scene = test::loadNamedScene("random20");
  const RenderOptions options = optionsForStage(Stage::optimized);
  EXPECT_TRUE(std::ranges::equal(render(RendererKind::simd_tbb, {}, scene, kOdd, options).pixels(),
                                 render(RendererKind::simd_only, {}, scene, kOdd, options).pixels()));
  SequentialRenderer sequential;
  EXPECT_TRUE(std::ranges::equal(render(RendererKind::tbb_only, {}, scene, kOdd, options).pixels(),
                                 test::renderFrame(sequential, scene, kOdd, options, kFrame).pixels()));
}

// main() answers RendererUnavailable with exit code 2, the lanes error included.
static_assert(std::is_base_of_v<RendererUnavailable, LanesUnsupported>);

// --lanes 4/8/16 exist exactly where the target's vectors hold that many floats.
TEST(Lanes, FollowTheTargetOnEveryTarget) {
  for (const std::int64_t target : simd::availableTargets()) {
    const simd::ScopedTargetOverride force(target);
    const int native = simd::dispatchedKernels().nativeLanes;
    ParallelSettings settings;
    EXPECT_EQ(makeRenderer(RendererKind::simd_only, settings)->info().lanes, native);
    for (const int lanes : {4, 8, 16}) {
      settings.lanes = lanes;
      if (lanes <= native) {
        EXPECT_EQ(makeRenderer(RendererKind::simd_only, settings)->info().lanes, lanes) << simd::targetName(target);
      } else {
        EXPECT_THROW(makeRenderer(RendererKind::simd_only, settings), LanesUnsupported) << simd::targetName(target);
      }
    }
  }
  // The override is lifted again: dispatch is back to the best target.
  EXPECT_EQ(simd::dispatchedKernels().target, simd::availableTargets().front());
}

TEST(Lanes, NativeIsTheBestTargetsWidth) {
  const auto targets = simd::availableTargets();
  ASSERT_FALSE(targets.empty());
  const RendererInfo info = makeRenderer(RendererKind::simd_tbb)->info();
  EXPECT_EQ(info.simdTarget, simd::targetName(targets.front()));
  EXPECT_EQ(info.lanes, simd::dispatchedKernels().nativeLanes);
}

TEST(RendererInfo, ReportsTheParallelSettings) {
  const RendererInfo tbb = makeRenderer(RendererKind::simd_tbb, threads(3, Partition::tiles, 5))->info();
  EXPECT_EQ(tbb.kind, RendererKind::simd_tbb);
  EXPECT_EQ(tbb.threads, 3);
  EXPECT_EQ(tbb.grain, 5);
  EXPECT_EQ(tbb.partition, Partition::tiles);
  EXPECT_FALSE(tbb.simdTarget.empty());

  const RendererInfo simdOnly = makeRenderer(RendererKind::simd_only)->info();
  EXPECT_EQ(simdOnly.threads, 1);
  EXPECT_FALSE(simdOnly.grain);
  EXPECT_FALSE(simdOnly.partition);

  const RendererInfo tbbOnly = makeRenderer(RendererKind::tbb_only, threads(2))->info();
  EXPECT_EQ(tbbOnly.threads, 2);
  EXPECT_EQ(tbbOnly.lanes, 1);
  EXPECT_TRUE(tbbOnly.simdTarget.empty());
  EXPECT_EQ(tbbOnly.grain, 1);
}

// Images narrower than one packet, and every remainder of 16 lanes.
TEST(PartialPackets, NarrowImagesAgreeWithSequential) {
  const Scene scene = test::loadNamedScene("default");
  const RenderOptions options = optionsForStage(Stage::optimized);
  SequentialRenderer sequential;
  const auto renderer = makeRenderer(RendererKind::simd_only);
  for (int width = 1; width <= 17; ++width) {
    const Extent extent{width, 5};
    const Image want = test::renderFrame(sequential, scene, extent, options, kFrame);
    const Image got = test::renderFrame(*renderer, scene, extent, options, kFrame);
    const ImageAgreement a = compareImages(got, want);
    EXPECT_LE(a.maxChannelDifference, 2) << "width " << width << ": " << test::describe(a);
  }
}

// The scenes' shininess is whole (32); a fractional one takes exp(e log x).
TEST(Shading, FractionalShininessAgreesWithSequential) {
  Scene scene = test::loadNamedScene("default");
  scene.render.shininess = 12.5f;
  SequentialRenderer sequential;
  const RenderOptions options = optionsForStage(Stage::optimized);
  const Image want = test::renderFrame(sequential, scene, {96, 64}, options, kFrame);
  for (const std::int64_t target : simd::availableTargets()) {
    const simd::ScopedTargetOverride force(target);
    const auto renderer = makeRenderer(RendererKind::simd_only);
    const ImageAgreement a = compareImages(test::renderFrame(*renderer, scene, {96, 64}, options, kFrame), want);
    EXPECT_TRUE(a.agrees()) << simd::targetName(target) << ": " << test::describe(a);
  }
}

TEST(RowScheduler, HandsOutEveryPixelOnceWithAlignedSpans) {
  const Extent extent{203, 19};
  for (const Partition partition : {Partition::rows, Partition::tiles}) {
    for (const int alignment : {1, 4, 16}) {
      RowScheduler scheduler(3, 2, partition);
      std::vector<std::atomic<int>> visits(extent.pixelCount());
      std::atomic<bool> misaligned = false, badSlot = false;
      scheduler.forEachSpan(extent, alignment, [&](int slot, int y, int x0, int x1) {
        if (x0 % alignment != 0) misaligned = true;
        if (slot < 0 || slot >= scheduler.threads()) badSlot = true;
        for (int x = x0; x < x1; ++x) ++visits[static_cast<std::size_t>(y) * extent.width + x];
      });
      EXPECT_FALSE(misaligned) << nameOf(partition) << " alignment " << alignment;
      EXPECT_FALSE(badSlot) << nameOf(partition);
      EXPECT_TRUE(std::ranges::all_of(visits, [](const std::atomic<int>& v) { return v == 1; }))
          << nameOf(partition) << " alignment " << alignment;
    }
  }
}

TEST(RowScheduler, RejectsBadSettings) {
  EXPECT_THROW(RowScheduler(-1, 1, Partition::rows), std::invalid_argument);
  EXPECT_THROW(RowScheduler(2, 0, Partition::rows), std::invalid_argument);
}

}  // namespace
}  // namespace rt
