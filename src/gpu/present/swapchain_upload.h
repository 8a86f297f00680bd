#pragma once
// The CPU renderers' Present phase in a window, behind a header without
// Vulkan: the app hands it to a CPU renderer as its FrameSink.
#include <memory>
#include <span>

#include "core/image.h"
#include "render/frame_sink.h"

namespace rt::gpu {

class Swapchain;

// The thesis' data path into a window: the frame is copied into a mapped
// staging buffer (one per frame in flight), vkCmdCopyBufferToImage moves it
// into an RGBA8 image on the device, and the swapchain blits that into the
// acquired image and presents it.
class SwapchainUpload final : public FrameSink {
 public:
  // Throws std::invalid_argument without a swapchain.
  explicit SwapchainUpload(std::shared_ptr<Swapchain> swapchain);
  ~SwapchainUpload() override;  // waits for the frames in flight

  void prepare(Extent extent) override;
  // Acquire, staging copy, upload, blit, present: the whole Present phase.
  void present(std::span<const Rgba8> frame) override;
  // The frame last handed to the window, from its staging buffer.
  void readBack(Image& target) override;

 private:
  struct Resources;
  Resources& prepared();  // throws std::logic_error before prepare()

  std::shared_ptr<Swapchain> swapchain_;
  std::unique_ptr<Resources> resources_;
};

}  // namespace rt::gpu
