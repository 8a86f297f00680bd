// The GPU renderer agrees with the sequential reference (docs/render-model.md
// section 8) on every scene, algorithm and bounce setting, at small sizes
// and at an odd one that leaves partial workgroups; all under validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "gpu/gpu_test_support.h"
#include "render/gpu_renderer.h"
#include "render/sequential_renderer.h"
#include "test_support.h"

namespace rt::test {
namespace {

// An orbiting frame, so the camera is not the scene file's.
constexpr long long kFrame = 25;

struct AgreementCase {
  const char* scene;
  Algorithm algorithm;
  bool bounce;
  Extent extent;
};

std::string caseName(const AgreementCase& c) {
  std::string name = std::string(c.scene) + "_" + std::string(nameOf(c.algorithm)) +
                     (c.bounce ? "_bounce_" : "_noexit_") + std::to_string(c.extent.width) + "x" +
                     std::to_string(c.extent.height);
  std::ranges::replace(name, '-', '_');
  return name;
}

// gtest's name for a case, and how it prints one in a failure.
std::string testName(const ::testing::TestParamInfo<AgreementCase>& info) { return caseName(info.param); }
void PrintTo(const AgreementCase& c, std::ostream* os) { *os << caseName(c); }

std::vector<AgreementCase> allCases() {
  std::vector<AgreementCase> cases;
  for (const char* scene : kSceneNames) {
    for (Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
      for (bool bounce : {true, false}) {
        for (Extent extent : {Extent{96, 64}, Extent{101, 37}}) cases.push_back({scene, algorithm, bounce, extent});
      }
    }
  }
  return cases;
}

RenderOptions optionsFor(Algorithm algorithm, bool bounce) {
  RenderOptions options{algorithm, EarlyExitSet()};
  if (bounce) options.earlyExits.add(EarlyExit::bounce);
  return options;
}

class GpuAgreement : public ValidatedGpuTest, public ::testing::WithParamInterface<AgreementCase> {};

TEST_P(GpuAgreement, AgreesWithTheSequentialRenderer) {
  const AgreementCase& c = GetParam();
  const Scene scene = loadNamedScene(c.scene);
  const RenderOptions options = optionsFor(c.algorithm, c.bounce);
  SequentialRenderer reference;
  GPURenderer gpu(presentSetup(PresentMode::upload));
  const Image expected = renderFrame(reference, scene, c.extent, options, kFrame);
  const Image actual = renderFrame(gpu, scene, c.extent, options, kFrame);
  const ImageAgreement agreement = compareImages(actual, expected);
  EXPECT_TRUE(agreement.agrees()) << describe(agreement);
}

INSTANTIATE_TEST_SUITE_P(AllScenesAlgorithmsAndSizes, GpuAgreement, ::testing::ValuesIn(allCases()), testName);

class GpuRendererTest : public ValidatedGpuTest {
 protected:
  const Scene scene_ = loadNamedScene("default");
  const RenderOptions options_ = optionsForStage(Stage::optimized);
};

// The agreement criterion is not met trivially: another frame of the same
// scene does not agree.
TEST_F(GpuRendererTest, AnotherFrameDoesNotAgree) {
  GPURenderer gpu(presentSetup(PresentMode::upload));
  SequentialRenderer reference;
  const Image gpuFrame = renderFrame(gpu, scene_, {96, 64}, options_, 0);
  const Image otherFrame = renderFrame(reference, scene_, {96, 64}, options_, 90);
  EXPECT_FALSE(compareImages(gpuFrame, otherFrame).agrees());
}

TEST_F(GpuRendererTest, PresentNoneAndUploadHandOnTheSameImage) {
  GPURenderer upload(presentSetup(PresentMode::upload));
  GPURenderer none(presentSetup(PresentMode::none));
  const Image viaPresentImage = renderFrame(upload, scene_, {101, 37}, options_, 7);
  const Image fromStorageImage = renderFrame(none, scene_, {101, 37}, options_, 7);
  EXPECT_TRUE(std::ranges::equal(viaPresentImage.pixels(), fromStorageImage.pixels()));
}

TEST_F(GpuRendererTest, ReadsBackTheSameFrameTwice) {
  GPURenderer gpu(presentSetup(PresentMode::none));
  const Image first = renderFrame(gpu, scene_, {40, 30}, options_, 3);
  Image again({40, 30});
  gpu.readPresented(again);
  EXPECT_TRUE(std::ranges::equal(first.pixels(), again.pixels()));
}

TEST_F(GpuRendererTest, MeasuresTheDispatchWithTimestamps) {
  if (context()->info().timestampValidBits == 0) GTEST_SKIP() << "the queue has no timestamps";
  GPURenderer gpu(presentSetup(PresentMode::upload));
  EXPECT_FALSE(gpu.lastGpuMs());
  gpu.prepare(scene_, {160, 120}, options_);
  const auto start = std::chrono::steady_clock::now();
  gpu.render(cameraAtFrame(scene_.camera, 0));
  const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(gpu.lastGpuMs());
  EXPECT_GT(*gpu.lastGpuMs(), 0.0);
  // The dispatch's device time is part of the host's record-submit-wait time.
  EXPECT_LE(*gpu.lastGpuMs(), wallMs * 1.05 + 0.05);
}

TEST_F(GpuRendererTest, PrepareAgainChangesSizeAndVariant) {
  GPURenderer gpu(presentSetup(PresentMode::upload));
  SequentialRenderer reference;
  (void)renderFrame(gpu, scene_, {101, 37}, options_, 0);
  const RenderOptions original = optionsForStage(Stage::original);
  const Image actual = renderFrame(gpu, scene_, {64, 48}, original, 5);
  const Image expected = renderFrame(reference, scene_, {64, 48}, original, 5);
  const ImageAgreement agreement = compareImages(actual, expected);
  EXPECT_TRUE(agreement.agrees()) << describe(agreement);
}

TEST_F(GpuRendererTest, ReadingBackBeforeAnyFrameIsAnError) {
  GPURenderer gpu(presentSetup(PresentMode::none));
  gpu.prepare(scene_, {16, 16}, options_);
  Image target({16, 16});
  EXPECT_THROW(gpu.readPresented(target), std::logic_error);
}

TEST_F(GpuRendererTest, ReportsItselfAsGpu) {
  const GPURenderer gpu(presentSetup(PresentMode::none));
  EXPECT_EQ(gpu.info().kind, RendererKind::gpu);
  EXPECT_EQ(gpu.info().threads, 0);
  EXPECT_EQ(gpu.info().lanes, 0);
}

TEST_F(GpuRendererTest, RenderingBeforePrepareIsAnError) {
  GPURenderer gpu(presentSetup(PresentMode::upload));
  EXPECT_THROW(gpu.render(cameraAtFrame(scene_.camera, 0)), std::logic_error);
}

TEST(GpuRendererWithoutDevice, IsRefused) { EXPECT_THROW(GPURenderer(PresentSetup{}), std::invalid_argument); }

}  // namespace
}  // namespace rt::test
