#include "render/sequential_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "render/double_reference.h"
#include "render/render_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr Extent kSmall{96, 64};
constexpr Extent kOdd{101, 37};
constexpr long long kFrames[] = {0, 30};

RenderOptions options(Algorithm algorithm, EarlyExitSet exits) { return {algorithm, exits}; }
const EarlyExitSet kBounceOnly = optionsForStage(Stage::single_pass).earlyExits;

class PerScene : public ::testing::TestWithParam<const char*> {
 protected:
  Scene scene = test::loadNamedScene(GetParam());
  SequentialRenderer renderer;
};

// Spec section 8: the float reference must itself agree with double precision.
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
      const Image single = test::renderFrame(renderer, scene, extent, options(Algorithm::single_pass, kBounceOnly), frame);
      const Image twoPass = test::renderFrame(renderer, scene, extent, options(Algorithm::two_pass, {}), frame);
      const ImageAgreement a = compareImages(single, twoPass);
      EXPECT_TRUE(a.agrees()) << extent.width << "x" << extent.height << " frame " << frame << ": " << test::describe(a);
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

}  // namespace
}  // namespace rt
