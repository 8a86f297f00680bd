#include "gpu/present/frame_upload.h"

#include <stdexcept>

#include "gpu/present/present_image.h"
#include "gpu/vulkan/context.h"

namespace rt::gpu {

// Declared in the order of creation: destroyed in reverse. The context
// (FrameUpload::context_) outlives them.
struct FrameUpload::Resources {
  Resources(const Device& d, Extent e) : device(d), extent(e) {}

  const Device& device;
  Extent extent;
  CommandRunner runner{device};
  PresentImage presentImage{device, runner, extent};
  Buffer staging{device, frameBytes(extent), vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::upload};
  Buffer readback{device, frameBytes(extent), vk::BufferUsageFlagBits::eTransferDst, MemoryUse::readback};
};

FrameUpload::FrameUpload(std::shared_ptr<Context> context) : context_(std::move(context)) {
  if (!context_) throw std::invalid_argument("FrameUpload needs a Vulkan context");
}

FrameUpload::~FrameUpload() = default;

void FrameUpload::prepare(Extent extent) {
  if (resources_ && resources_->extent == extent) return;
  resources_.reset();  // the old present image goes before the new one is made
  resources_ =
      translateVulkanErrors("present set-up", [&] { return std::make_unique<Resources>(context_->device(), extent); });
}

FrameUpload::Resources& FrameUpload::prepared() {
  if (!resources_) throw std::logic_error("FrameUpload: prepare() was not called");
  return *resources_;
}

void FrameUpload::present(std::span<const Rgba8> frame) {
  Resources& r = prepared();
  if (frame.size() != r.extent.pixelCount()) throw std::logic_error("FrameUpload: frame size differs from the extent");
  translateVulkanErrors("present", [&] {
    copyFromFrame(frame, r.staging);
    r.runner.run("present",
                 [&](const vk::raii::CommandBuffer& cb) { r.presentImage.recordCopyFrom(cb, r.staging.handle()); });
  });
}

void FrameUpload::readBack(Image& target) {
  Resources& r = prepared();
  if (target.extent() != r.extent) throw std::logic_error("FrameUpload: target extent differs");
  translateVulkanErrors("frame readback", [&] {
    r.runner.run("frame readback",
                 [&](const vk::raii::CommandBuffer& cb) { r.presentImage.recordReadback(cb, r.readback.handle()); });
    copyToImage(r.readback, target);
  });
}

}  // namespace rt::gpu
