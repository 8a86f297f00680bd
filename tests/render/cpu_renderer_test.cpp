// The CPU renderers, each a (kernel, scheduler) pair: the sequential
// reference against the double-precision model, and what the threaded ones
// must keep (thread counts change no pixel, settings reach RendererInfo).
#include <gtest/gtest.h>

#include <algorithm>

#include "render/accel/accel_scenes.h"
#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
#include "render/scalar/double_reference.h"
#include "render/scale_agreement.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr Extent kSmall{96, 64};
constexpr Extent kOdd{101, 37};
constexpr long long kFrames[] = {0, 30};
constexpr long long kFrame = 30;

RenderOptions options(Algorithm algorithm, EarlyExitSet exits) { return {algorithm, exits}; }

// The contracts of render/cpu_contracts.h tell the halves apart: each
// kernel and scheduler header asserts its own, these that they can fail.
static_assert(!CpuKernel<SerialScheduler>);
static_assert(!SpanScheduler<ScalarKernel>);
struct KernelWithoutAlignment {
  static constexpr Kernel kId = Kernel::scalar;
  explicit KernelWithoutAlignment(const ParallelSettings&) {}
  [[nodiscard]] int lanes() const { return 1; }
  [[nodiscard]] std::string simdTarget() const { return {}; }
  [[nodiscard]] std::optional<AccelStructureInfo> accelStructure() const { return std::nullopt; }
  void prepare(const Scene&, const RenderOptions&, int) {}
  void beginFrame(const CameraFrame&, Image&) {}
  void renderSpan(int, int, int, int) {}
};
static_assert(!CpuKernel<KernelWithoutAlignment>);
const EarlyExitSet kBounceOnly = optionsForStage(Stage::single_pass).earlyExits;

class PerScene : public ::testing::TestWithParam<const char*> {
 protected:
  Scene scene = test::loadNamedScene(GetParam());
  SequentialRenderer renderer;
};

// docs/render-model.md section 8: the float reference must itself agree with double precision.
TEST_P(PerScene, AgreesWithDoublePrecisionModel) {
  for (Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
    for (long long frame : kFrames) {
      const RenderOptions o = options(algorithm, kBounceOnly);
      const Image got = test::renderFrame(renderer, scene, kSmall, o, frame);
      const Image want = renderDoubleReference(scene, cameraAtFrame(scene.camera, frame), kSmall, o);
      const ImageAgreement a = compareImages(got, want);
      EXPECT_TRUE(a.agrees()) << nameOf(algorithm) << " frame " << frame << ": " << test::describe(a);
    }
  }
}

TEST_P(PerScene, SinglePassAgreesWithTwoPass) {
  for (Extent extent : {kSmall, kOdd}) {
    for (long long frame : kFrames) {
      const Image single =
          test::renderFrame(renderer, scene, extent, options(Algorithm::single_pass, kBounceOnly), frame);
      const Image twoPass = test::renderFrame(renderer, scene, extent, options(Algorithm::two_pass, {}), frame);
      const ImageAgreement a = compareImages(single, twoPass);
      EXPECT_TRUE(a.agrees()) << extent.width << "x" << extent.height << " frame " << frame << ": "
                              << test::describe(a);
    }
  }
}

// Without the bounce exit a dead ray adds exactly +0: the image is bit-identical.
TEST_P(PerScene, BounceEarlyExitDoesNotChangeThePicture) {
  for (Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
    const Image with = test::renderFrame(renderer, scene, kOdd, options(algorithm, kBounceOnly), 30);
    const Image without = test::renderFrame(renderer, scene, kOdd, options(algorithm, {}), 30);
    EXPECT_TRUE(std::ranges::equal(with.pixels(), without.pixels())) << nameOf(algorithm);
  }
}

TEST_P(PerScene, OrbitMovesThePicture) {
  const RenderOptions o = optionsForStage(Stage::optimized);
  const Image first = test::renderFrame(renderer, scene, kSmall, o, 0);
  const Image later = test::renderFrame(renderer, scene, kSmall, o, 30);
  EXPECT_FALSE(compareImages(first, later).agrees());
}

INSTANTIATE_TEST_SUITE_P(Scenes, PerScene, ::testing::ValuesIn(test::kSceneNames));

TEST(SequentialRenderer, ReportsItsConfiguration) {
  const RendererInfo info = SequentialRenderer().info();
  EXPECT_EQ(info.kind, RendererKind::sequential);
  EXPECT_EQ(info.threads, 1);
  EXPECT_EQ(info.lanes, 1);
  EXPECT_TRUE(info.simdTarget.empty());
}

TEST(SequentialRenderer, MaxDepthOneShowsNoReflections) {
  Scene scene = test::loadNamedScene("default");
  SequentialRenderer renderer;
  const RenderOptions o = optionsForStage(Stage::optimized);
  const Image deep = test::renderFrame(renderer, scene, kSmall, o, 0);
  scene.render.maxDepth = 1;
  const Image flat = test::renderFrame(renderer, scene, kSmall, o, 0);
  EXPECT_FALSE(std::ranges::equal(deep.pixels(), flat.pixels()));
}

Image render(RendererKind kind, const ParallelSettings& settings, const Scene& scene, Extent extent,
             const RenderOptions& options) {
  // One renderer at a time: each holds a process-wide oneTBB thread limit.
  const auto renderer = makeCpuRenderer(kind, settings);
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

TEST(RendererInfo, ReportsTheParallelSettings) {
  const RendererInfo tbb = makeCpuRenderer(RendererKind::simd_tbb, threads(3, Partition::tiles, 5))->info();
  EXPECT_EQ(tbb.kind, RendererKind::simd_tbb);
  EXPECT_EQ(tbb.threads, 3);
  EXPECT_EQ(tbb.grain, 5);
  EXPECT_EQ(tbb.partition, Partition::tiles);
  EXPECT_FALSE(tbb.simdTarget.empty());

  const RendererInfo simdOnly = makeCpuRenderer(RendererKind::simd_only)->info();
  EXPECT_EQ(simdOnly.threads, 1);
  EXPECT_FALSE(simdOnly.grain);
  EXPECT_FALSE(simdOnly.partition);

  const RendererInfo tbbOnly = makeCpuRenderer(RendererKind::tbb_only, threads(2))->info();
  EXPECT_EQ(tbbOnly.threads, 2);
  EXPECT_EQ(tbbOnly.lanes, 1);
  EXPECT_TRUE(tbbOnly.simdTarget.empty());
  EXPECT_EQ(tbbOnly.grain, 1);
}

// A camera inside a large sphere: secondary rays leave it from inside, and
// with the normal facing the ray (docs/render-model.md section 4) every
// renderer still agrees with double precision (without it, float and double
// disagreed on about a quarter of the pixels).
TEST(EveryCpuRenderer, CameraInsideASphereAgreesWithDoublePrecision) {
  const Scene scene = test::cameraInsideSky();
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    const auto kind = static_cast<RendererKind>(i);
    if (!cpuRendererBuilt(kind)) continue;
    for (const Stage stage : {Stage::original, Stage::optimized}) {
      const RenderOptions o = optionsForStage(stage);
      const Image got = render(kind, threads(2), scene, kSmall, o);
      const Image want = renderDoubleReference(scene, cameraAtFrame(scene.camera, kFrame), kSmall, o);
      const ImageAgreement a = compareImages(got, want);
      EXPECT_TRUE(a.agrees()) << nameOf(kind) << " " << nameOf(stage) << ": " << test::describe(a);
    }
  }
}

// docs/render-model.md section 8 at scale: 100,000 spheres, each CPU
// renderer with each --accel it accepts, against the double reference (on
// the BVH) under the rule at scale.
TEST(EveryCpuRenderer, AgreesWithDoublePrecisionAt100000Spheres) {
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    const auto kind = static_cast<RendererKind>(i);
    if (!cpuRendererBuilt(kind)) continue;
    for (const Accel accel : {Accel::bvh, Accel::none}) {
      if (definitionOf(kind).ownAccel && accel != *definitionOf(kind).ownAccel) continue;
      const auto renderer = makeCpuRenderer(kind, threads(2));
      const AgreementBreakdown b = test::scaleAgreement(*renderer, accel);
      EXPECT_TRUE(b.agreesAtScale()) << nameOf(kind) << " --accel " << nameOf(accel) << ": " << test::describe(b);
    }
  }
}

// The rule at scale still fails a renderer with a defect: the sequential
// renderer given the scene as a bug would see it, against the true scene's
// reference.
TEST(RuleAtScale, CatchesDefectsInTheRenderer) {
  struct Defect {
    const char* name;
    void (*apply)(Scene&);
  };
  const Defect defects[] = {
      {"reflectivity 10 % low (the bounce's throughput)", [](Scene& s) { s.render.reflectivity *= 0.9f; }},
      {"two bounces too few", [](Scene& s) { s.render.maxDepth -= 2; }},
      {"spheres 1 % larger (the intersection)",
       [](Scene& s) {
         for (Sphere& sphere : s.spheres) sphere.radius *= 1.01f;
       }},
      {"ambient light 0.1 -> 0.11 (the shading)", [](Scene& s) { s.lightData.ambientLightColor *= 1.1f; }},
  };
  for (const Defect& defect : defects) {
    Scene broken = test::scaleScene();
    defect.apply(broken);
    SequentialRenderer renderer;
    const AgreementBreakdown b = test::scaleAgreement(renderer, Accel::bvh, broken);
    EXPECT_FALSE(b.agreesAtScale()) << defect.name << ": " << test::describe(b);
  }
}

// The schema names each CPU renderer's pair; the factory builds exactly that.
TEST(CpuRendererFactory, BuildsThePairTheSchemaNames) {
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    const auto kind = static_cast<RendererKind>(i);
    if (!cpuRendererBuilt(kind)) {
      EXPECT_THROW(makeCpuRenderer(kind), RendererUnavailable) << nameOf(kind);
      continue;
    }
    const RendererInfo info = makeCpuRenderer(kind, threads(2))->info();
    EXPECT_EQ(info.kind, kind);
    EXPECT_EQ(info.simdTarget.empty(), definitionOf(kind).kernel == Kernel::scalar) << nameOf(kind);
    EXPECT_EQ(info.partition.has_value(), definitionOf(kind).scheduler == Scheduler::tbb) << nameOf(kind);
  }
}

}  // namespace
}  // namespace rt
