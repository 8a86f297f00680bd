#pragma once
// The CPU renderers' Present phase on a Vulkan device, behind a header
// without Vulkan (src/render includes it).
#include <memory>
#include <span>

#include "core/image.h"

namespace rt::gpu {

class Context;

// The thesis' data path for the CPU renderers: the frame is copied into a
// mapped host-visible staging buffer, and vkCmdCopyBufferToImage moves it
// into the present image, as it moved into the swapchain image there.
class FrameUpload {
 public:
  FrameUpload(std::shared_ptr<Context> context, Extent extent);
  ~FrameUpload();
  FrameUpload(const FrameUpload&) = delete;
  FrameUpload& operator=(const FrameUpload&) = delete;

  [[nodiscard]] Extent extent() const;
  // Staging copy, submit, wait: the whole Present phase.
  void present(std::span<const Rgba8> frame);
  // The present image's contents, back on the host (saved frames, tests).
  void readBack(Image& target);

 private:
  struct Resources;
  std::unique_ptr<Resources> resources_;
};

}  // namespace rt::gpu
