// The CPU renderers' Present phase on a Vulkan device: the frame upload
// through a staging buffer into the present image (gpu::makeFrameUpload,
// the FrameSink the app hands them), under validation.
#include "gpu/present/frame_upload.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "gpu/gpu_test_support.h"
#include "render/cpu_renderers.h"
#include "test_support.h"

namespace rt::test {
namespace {

class FrameUploadTest : public ValidatedGpuTest {
 protected:
  const Scene scene_ = loadNamedScene("random20");
  const RenderOptions options_ = optionsForStage(Stage::optimized);
};

// What reaches the present image is exactly the working buffer.
TEST_F(FrameUploadTest, CpuUploadRoundTripsTheFrameExactly) {
  SequentialRenderer uploading({}, gpu::makeFrameUpload(context()));
  SequentialRenderer local;
  const Image viaDevice = renderFrame(uploading, scene_, {101, 37}, options_, 4);
  const Image fromMemory = renderFrame(local, scene_, {101, 37}, options_, 4);
  EXPECT_TRUE(std::ranges::equal(viaDevice.pixels(), fromMemory.pixels()));
}

TEST_F(FrameUploadTest, HandsOnEachNewFrameAndFollowsTheExtent) {
  const std::unique_ptr<FrameSink> upload = gpu::makeFrameUpload(context());
  for (const Extent extent : {Extent{3, 2}, Extent{5, 4}}) {
    upload->prepare(extent);
    Image frame(extent);
    Image back(extent);
    for (std::uint8_t value : {std::uint8_t{10}, std::uint8_t{200}}) {
      std::ranges::fill(frame.pixels(), Rgba8{value, std::uint8_t(value + 1), std::uint8_t(value + 2), 255});
      upload->present(frame.pixels());
      upload->readBack(back);
      EXPECT_TRUE(std::ranges::equal(frame.pixels(), back.pixels())) << "value " << int(value);
    }
  }
}

TEST_F(FrameUploadTest, RefusesUseBeforePrepareAndWithoutDevice) {
  const std::unique_ptr<FrameSink> upload = gpu::makeFrameUpload(context());
  const Image frame({3, 2});
  EXPECT_THROW(upload->present(frame.pixels()), std::logic_error);
  EXPECT_THROW(gpu::makeFrameUpload(nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace rt::test
