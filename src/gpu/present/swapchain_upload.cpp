#include "gpu/present/swapchain_upload.h"

#include <stdexcept>
#include <vector>

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

}  // namespace

struct SwapchainUpload::Resources {
  Resources(const Device& device, Extent e)
      : extent(e),
        frame(device, e, vk::ImageUsageFlagBits::eTransferDst | vk::ImageUsageFlagBits::eTransferSrc),
        staging(stagingBuffers(device, e)) {}

  Extent extent;
  DeviceImage frame;            // the uploaded frame, the blit's source
  std::vector<Buffer> staging;  // one per frame slot: the host fills one while the other's copy runs
  std::size_t lastSlot = 0;
  bool presented = false;
};

SwapchainUpload::SwapchainUpload(std::shared_ptr<Swapchain> swapchain) : swapchain_(std::move(swapchain)) {
  if (!swapchain_) throw std::invalid_argument("SwapchainUpload needs a swapchain");
}

SwapchainUpload::~SwapchainUpload() {
  try {
    swapchain_->device().logical().waitIdle();  // the last frames still read the buffers and the image
  } catch (const vk::SystemError&) {
    // A lost device runs nothing that could read them.
  }
}

void SwapchainUpload::prepare(Extent extent) {
  if (resources_ && resources_->extent == extent) return;
  translateVulkanErrors("present set-up", [&] {
    swapchain_->device().logical().waitIdle();
    resources_.reset();
    resources_ = std::make_unique<Resources>(swapchain_->device(), extent);
  });
}

SwapchainUpload::Resources& SwapchainUpload::prepared() {
  if (!resources_) throw std::logic_error("SwapchainUpload: prepare() was not called");
  return *resources_;
}

void SwapchainUpload::present(std::span<const Rgba8> frame) {
  Resources& r = prepared();
  if (frame.size() != r.extent.pixelCount())
    throw std::logic_error("SwapchainUpload: frame size differs from the extent");
  translateVulkanErrors("present", [&] {
    swapchain_->present(r.frame.handle(), r.extent, [&](const vk::raii::CommandBuffer& cb, std::uint32_t slot) {
      // The slot's fence has signalled: its last copy out of this buffer is done.
      const Buffer& staging = r.staging[slot];
      copyFromFrame(frame, staging);
      // The previous frame's blit out of the image (an earlier submission) is done before it is overwritten.
      imageBarrier(cb, r.frame.handle(), {Stage::eTransfer, {}, Layout::eUndefined},
                   {Stage::eTransfer, Access::eTransferWrite, Layout::eTransferDstOptimal});
      cb.copyBufferToImage(staging.handle(), r.frame.handle(), Layout::eTransferDstOptimal, wholeImageRegion(r.extent));
      imageBarrier(cb, r.frame.handle(), {Stage::eTransfer, Access::eTransferWrite, Layout::eTransferDstOptimal},
                   {Stage::eTransfer, Access::eTransferRead, Layout::eTransferSrcOptimal});
      r.lastSlot = slot;
      r.presented = true;
    });
  });
}

void SwapchainUpload::readBack(Image& target) {
  const Resources& r = prepared();
  if (target.extent() != r.extent) throw std::logic_error("SwapchainUpload: target extent differs");
  if (!r.presented) throw std::logic_error("SwapchainUpload: no frame presented yet");
  copyToImage(r.staging[r.lastSlot], target);
}

}  // namespace rt::gpu
