// The default scene at 160x120, frames 0 and 30, against committed PNGs.
// The references are renders of the double-precision model; regenerate them
// (only after a deliberate change of the model) with
//   RT_UPDATE_GOLDEN=1 build/debug/tests/rt_tests --gtest_filter='GoldenImage.*'
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
#include "render/scalar/double_reference.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr Extent kGoldenExtent{160, 120};

std::filesystem::path goldenPath(long long frame) {
  return test::sourceDir() / "tests" / "render" / "golden" / ("default_160x120_frame" + std::to_string(frame) + ".png");
}

class GoldenImage : public ::testing::TestWithParam<long long> {};

TEST_P(GoldenImage, SequentialRendererMatchesCommittedReference) {
  const long long frame = GetParam();
  const Scene scene = test::loadNamedScene("default");
  const RenderOptions options = optionsForStage(Stage::optimized);
  if (std::getenv("RT_UPDATE_GOLDEN") != nullptr) {
    writePng(renderDoubleReference(scene, cameraAtFrame(scene.camera, frame), kGoldenExtent, options),
             goldenPath(frame));
  }
  const Image reference = readPng(goldenPath(frame));
  ASSERT_EQ(reference.extent(), kGoldenExtent);
  SequentialRenderer renderer;
  const Image image = test::renderFrame(renderer, scene, kGoldenExtent, options, frame);
  const ImageAgreement a = compareImages(image, reference);
  EXPECT_TRUE(a.agrees()) << test::describe(a);
}

INSTANTIATE_TEST_SUITE_P(DefaultScene, GoldenImage, ::testing::Values(0LL, 30LL));

}  // namespace
}  // namespace rt
