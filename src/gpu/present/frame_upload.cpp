#include "gpu/present/frame_upload.h"

#include <stdexcept>

#include "gpu/present/present_image.h"
#include "gpu/present/staged_upload.h"
#include "gpu/vulkan/context.h"

namespace rt::gpu {
namespace {

// What prepare() makes for one extent, declared in the order of creation:
// destroyed in reverse. The context (StagedUpload's destination) outlives them.
struct PresentImageResources {
  PresentImageResources(const Device& d, Extent e) : device(d), extent(e) {}

  const Device& device;
  Extent extent;
  CommandRunner runner{device};
  PresentImage presentImage{device, runner, extent};
  Buffer staging{device, frameBytes(extent), vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::upload};
  Buffer readback{device, frameBytes(extent), vk::BufferUsageFlagBits::eTransferDst, MemoryUse::readback};
};

class FrameUpload final : public StagedUpload<Context, PresentImageResources> {
 public:
  explicit FrameUpload(std::shared_ptr<Context> context)
      : StagedUpload("FrameUpload", std::move(context), "a Vulkan context") {}

 private:
  void replace(std::unique_ptr<PresentImageResources>& resources, Extent extent) override {
    resources.reset();  // the old present image goes before the new one is made
    resources = translateVulkanErrors(
        "present set-up", [&] { return std::make_unique<PresentImageResources>(destination().device(), extent); });
  }

  // Staging copy, submit, wait: the whole Present phase.
  void upload(PresentImageResources& r, std::span<const Rgba8> frame) override {
    translateVulkanErrors("present", [&] {
      copyFromFrame(frame, r.staging);
      r.runner.run("present",
                   [&](const vk::raii::CommandBuffer& cb) { r.presentImage.recordCopyFrom(cb, r.staging.handle()); });
    });
  }

  // The present image's contents, back on the host (saved frames, tests).
  void download(PresentImageResources& r, Image& target) override {
    translateVulkanErrors("frame readback", [&] {
      r.runner.run("frame readback",
                   [&](const vk::raii::CommandBuffer& cb) { r.presentImage.recordReadback(cb, r.readback.handle()); });
      copyToImage(r.readback, target);
    });
  }
};

}  // namespace

std::unique_ptr<FrameSink> makeFrameUpload(std::shared_ptr<Context> context) {
  return std::make_unique<FrameUpload>(std::move(context));
}

}  // namespace rt::gpu
