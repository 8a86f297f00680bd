// The Present phase on a Vulkan device: the CPU renderers' upload through
// a staging buffer, and the frame loop's use of present, readback and GPU
// timestamps; all under validation.
#include <gtest/gtest.h>

#include <algorithm>

#include "app/frame_loop.h"
#include "gpu/frame_upload.h"
#include "gpu_test_support.h"
#include "render/gpu_renderer.h"
#include "render/sequential_renderer.h"
#include "test_support.h"

namespace rt::test {
namespace {

class PresentTest : public ValidatedGpuTest {
 protected:
  const Scene scene_ = loadNamedScene("random20");
  const RenderOptions options_ = optionsForStage(Stage::optimized);
};

// What reaches the present image is exactly the working buffer.
TEST_F(PresentTest, CpuUploadRoundTripsTheFrameExactly) {
  SequentialRenderer uploading;
  uploading.setPresentSetup(presentSetup(PresentMode::upload));
  SequentialRenderer local;
  const Image viaDevice = renderFrame(uploading, scene_, {101, 37}, options_, 4);
  const Image fromMemory = renderFrame(local, scene_, {101, 37}, options_, 4);
  EXPECT_TRUE(std::ranges::equal(viaDevice.pixels(), fromMemory.pixels()));
}

TEST_F(PresentTest, FrameUploadHandsOnEachNewFrame) {
  gpu::FrameUpload upload(context(), {3, 2});
  Image frame({3, 2});
  Image back({3, 2});
  for (std::uint8_t value : {std::uint8_t{10}, std::uint8_t{200}}) {
    std::ranges::fill(frame.pixels(), Rgba8{value, std::uint8_t(value + 1), std::uint8_t(value + 2), 255});
    upload.present(frame.pixels());
    upload.readBack(back);
    EXPECT_TRUE(std::ranges::equal(frame.pixels(), back.pixels())) << "value " << int(value);
  }
}

TEST_F(PresentTest, UploadWithoutDeviceIsRefused) {
  SequentialRenderer renderer;
  EXPECT_THROW(renderer.setPresentSetup({PresentMode::upload, nullptr}), std::invalid_argument);
}

RunConfig smallRun() {
  RunConfig config;
  config.extent = {64, 48};
  config.warmupFrames = 1;
  config.measuredFrames = 3;
  config.saveFrames = {{2, "unused.png"}};
  return config;
}

// Forwards to a renderer and counts the readbacks the frame loop asks for.
class CountingReadbacks final : public Renderer {
 public:
  explicit CountingReadbacks(Renderer& inner) : inner_(inner) {}
  [[nodiscard]] RendererInfo info() const override { return inner_.info(); }
  void prepare(const Scene& s, Extent e, const RenderOptions& o) override { inner_.prepare(s, e, o); }
  void render(const CameraFrame& camera) override { inner_.render(camera); }
  void present() override { inner_.present(); }
  void readPresented(Image& target) override {
    ++readbacks;
    inner_.readPresented(target);
  }
  [[nodiscard]] std::optional<double> lastGpuMs() const override { return inner_.lastGpuMs(); }
  int readbacks = 0;

 private:
  Renderer& inner_;
};

TEST_F(PresentTest, FrameLoopRecordsGpuTimeAndReadsBackOnlySavedFrames) {
  if (context()->info().timestampValidBits == 0) GTEST_SKIP() << "the queue has no timestamps";
  const RunConfig config = smallRun();
  GPURenderer gpu(presentSetup(PresentMode::upload));
  CountingReadbacks counting(gpu);
  const FrameLoopResult result = runFrameLoop(counting, scene_, config);
  ASSERT_FALSE(result.failure);
  ASSERT_EQ(result.records.size(), 4u);
  EXPECT_EQ(counting.readbacks, 1) << "one saved frame, one readback";
  for (const FrameRecord& r : result.records) {
    ASSERT_TRUE(r.gpuMs) << "frame " << r.frame;
    EXPECT_GT(*r.gpuMs, 0.0);
    EXPECT_LE(*r.gpuMs, r.renderMs * 1.05 + 0.05);
  }
  SequentialRenderer reference;
  const Image expected = renderFrame(reference, scene_, config.extent, config.options, 2);
  const ImageAgreement agreement = compareImages(result.savedFrames[0], expected);
  EXPECT_TRUE(agreement.agrees()) << describe(agreement);
}

TEST_F(PresentTest, CpuFramesHaveNoGpuTime) {
  SequentialRenderer renderer;
  renderer.setPresentSetup(presentSetup(PresentMode::upload));
  const FrameLoopResult result = runFrameLoop(renderer, scene_, smallRun());
  ASSERT_FALSE(result.failure);
  EXPECT_TRUE(std::ranges::none_of(result.records, [](const FrameRecord& r) { return r.gpuMs.has_value(); }));
}

// A renderer whose device is lost at frame 2: the frames before it are
// kept, and the error says what happened.
class LosesDeviceAtFrameTwo final : public Renderer {
 public:
  [[nodiscard]] RendererInfo info() const override {
    RendererInfo info;
    info.kind = RendererKind::gpu;
    return info;
  }
  void prepare(const Scene&, Extent, const RenderOptions&) override {}
  void render(const CameraFrame&) override {
    if (frames_++ == 2) throw gpu::DeviceError("Vulkan failure during render: ErrorDeviceLost");
  }
  void present() override {}
  void readPresented(Image&) override {}

 private:
  int frames_ = 0;
};

TEST(DeviceLoss, KeepsTheFramesAlreadyRecorded) {
  LosesDeviceAtFrameTwo renderer;
  const FrameLoopResult result = runFrameLoop(renderer, loadNamedScene("default"), smallRun());
  EXPECT_EQ(result.records.size(), 2u);
  ASSERT_TRUE(result.failure);
  EXPECT_THROW(std::rethrow_exception(result.failure), gpu::DeviceError);
}

}  // namespace
}  // namespace rt::test
