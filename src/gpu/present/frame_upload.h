#pragma once
// The CPU renderers' Present phase on a Vulkan device, behind a header
// without Vulkan: the app hands it to a CPU renderer as its FrameSink.
#include <memory>
#include <span>

#include "core/image.h"
#include "render/frame_sink.h"

namespace rt::gpu {

class Context;

// The thesis' data path for the CPU renderers: the frame is copied into a
// mapped host-visible staging buffer, and vkCmdCopyBufferToImage moves it
// into the present image, as it moved into the swapchain image there.
class FrameUpload final : public FrameSink {
 public:
  // Throws std::invalid_argument without a context.
  explicit FrameUpload(std::shared_ptr<Context> context);
  ~FrameUpload() override;

  // Makes the present image and buffers for `extent` (again only when it changes).
  void prepare(Extent extent) override;
  // Staging copy, submit, wait: the whole Present phase.
  void present(std::span<const Rgba8> frame) override;
  // The present image's contents, back on the host (saved frames, tests).
  void readBack(Image& target) override;

 private:
  struct Resources;
  Resources& prepared();  // throws std::logic_error before prepare()

  std::shared_ptr<Context> context_;
  std::unique_ptr<Resources> resources_;
};

}  // namespace rt::gpu
