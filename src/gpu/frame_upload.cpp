#include "gpu/frame_upload.h"

#include <cstring>
#include <stdexcept>

#include "gpu/context.h"
#include "gpu/present_image.h"

namespace rt::gpu {

// Declared in the order of creation: destroyed in reverse, the context last.
struct FrameUpload::Resources {
  Resources(std::shared_ptr<Context> c, Extent e) : context(std::move(c)), extent(e) {}

  std::shared_ptr<Context> context;
  Extent extent;
  CommandRunner runner{context->device()};
  PresentImage presentImage{context->device(), runner, extent};
  Buffer staging{context->device(), frameBytes(extent), vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::upload};
  Buffer readback{context->device(), frameBytes(extent), vk::BufferUsageFlagBits::eTransferDst, MemoryUse::readback};
};

FrameUpload::FrameUpload(std::shared_ptr<Context> context, Extent extent) {
  if (!context) throw std::invalid_argument("FrameUpload needs a Vulkan context");
  resources_ = translateVulkanErrors("present set-up", [&] {
    return std::make_unique<Resources>(std::move(context), extent);
  });
}

FrameUpload::~FrameUpload() = default;

Extent FrameUpload::extent() const { return resources_->extent; }

void FrameUpload::present(std::span<const Rgba8> frame) {
  Resources& r = *resources_;
  if (frame.size() != r.extent.pixelCount()) throw std::logic_error("FrameUpload: frame size differs from the extent");
  translateVulkanErrors("present", [&] {
    std::memcpy(r.staging.mapped().data(), frame.data(), frame.size_bytes());
    // Host writes before the submission need no barrier; non-coherent memory needs a flush.
    r.staging.flushHostWrites();
    r.runner.run("present", [&](const vk::raii::CommandBuffer& cb) { r.presentImage.recordCopyFrom(cb, r.staging.handle()); });
  });
}

void FrameUpload::readBack(Image& target) {
  Resources& r = *resources_;
  if (target.extent() != r.extent) throw std::logic_error("FrameUpload: target extent differs");
  translateVulkanErrors("frame readback", [&] {
    r.runner.run("frame readback",
                 [&](const vk::raii::CommandBuffer& cb) { r.presentImage.recordReadback(cb, r.readback.handle()); });
    copyToImage(r.readback, target);
  });
}

}  // namespace rt::gpu
