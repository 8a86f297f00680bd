#include "gpu/present/swapchain_upload.h"

#include <stdexcept>
#include <vector>

#include "gpu/present/staged_upload.h"
#include "gpu/present/swapchain.h"

namespace rt::gpu {
namespace {

using Stage = vk::PipelineStageFlagBits;
using Access = vk::AccessFlagBits;
using Layout = vk::ImageLayout;

std::vector<Buffer> stagingBuffers(const Device& device, Extent extent) {
  std::vector<Buffer> buffers;
  for (std::uint32_t i = 0; i < Swapchain::kFramesInFlight; ++i) {
    buffers.emplace_back(device, frameBytes(extent), vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::upload);
  }
  return buffers;
}

// What prepare() makes for one extent.
struct WindowUploadResources {
  WindowUploadResources(const Device& device, Extent e)
      : extent(e),
        frame(device, e, vk::ImageUsageFlagBits::eTransferDst | vk::ImageUsageFlagBits::eTransferSrc),
        staging(stagingBuffers(device, e)) {}

  Extent extent;
  DeviceImage frame;            // the uploaded frame, the blit's source
  std::vector<Buffer> staging;  // one per frame slot: the host fills one while the other's copy runs
  std::size_t lastSlot = 0;
  bool presented = false;
};

class SwapchainUpload final : public StagedUpload<Swapchain, WindowUploadResources> {
 public:
  explicit SwapchainUpload(std::shared_ptr<Swapchain> swapchain)
      : StagedUpload("SwapchainUpload", std::move(swapchain), "a swapchain") {}

  ~SwapchainUpload() override {
    try {
      destination().device().logical().waitIdle();  // the last frames still read the buffers and the image
    } catch (const vk::SystemError&) {
      // A lost device runs nothing that could read them.
    }
  }

 private:
  void replace(std::unique_ptr<WindowUploadResources>& resources, Extent extent) override {
    translateVulkanErrors("present set-up", [&] {
      destination().device().logical().waitIdle();
      resources.reset();
      resources = std::make_unique<WindowUploadResources>(destination().device(), extent);
    });
  }

  // Acquire, staging copy, upload, blit, present: the whole Present phase.
  void upload(WindowUploadResources& r, std::span<const Rgba8> frame) override {
    translateVulkanErrors("present", [&] {
      destination().present(r.frame.handle(), r.extent, [&](const vk::raii::CommandBuffer& cb, std::uint32_t slot) {
        // The slot's fence has signalled: its last copy out of this buffer is done.
        const Buffer& staging = r.staging[slot];
        copyFromFrame(frame, staging);
        // The previous frame's blit out of the image (an earlier submission) is done before it is overwritten.
        imageBarrier(cb, r.frame.handle(), {Stage::eTransfer, {}, Layout::eUndefined},
                     {Stage::eTransfer, Access::eTransferWrite, Layout::eTransferDstOptimal});
        cb.copyBufferToImage(staging.handle(), r.frame.handle(), Layout::eTransferDstOptimal,
                             wholeImageRegion(r.extent));
        imageBarrier(cb, r.frame.handle(), {Stage::eTransfer, Access::eTransferWrite, Layout::eTransferDstOptimal},
                     {Stage::eTransfer, Access::eTransferRead, Layout::eTransferSrcOptimal});
        r.lastSlot = slot;
        r.presented = true;
      });
    });
  }

  // The frame last handed to the window, from its staging buffer.
  void download(WindowUploadResources& r, Image& target) override {
    if (!r.presented) throw std::logic_error("SwapchainUpload: no frame presented yet");
    copyToImage(r.staging[r.lastSlot], target);
  }
};

}  // namespace

std::unique_ptr<FrameSink> makeSwapchainUpload(std::shared_ptr<Swapchain> swapchain) {
  return std::make_unique<SwapchainUpload>(std::move(swapchain));
}

}  // namespace rt::gpu
