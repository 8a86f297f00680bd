#include "gpu/present/present_image.h"

namespace rt::gpu {
namespace {

using Stage = vk::PipelineStageFlagBits;
using Access = vk::AccessFlagBits;
using Layout = vk::ImageLayout;

constexpr ImageState kSteady{Stage::eTransfer, Access::eTransferWrite, Layout::eTransferDstOptimal};

vk::ImageCopy wholeImageCopy(Extent extent) {
  const vk::ImageSubresourceLayers layers{vk::ImageAspectFlagBits::eColor, 0, 0, 1};
  return vk::ImageCopy{
      .srcSubresource = layers,
      .srcOffset = {0, 0, 0},
      .dstSubresource = layers,
      .dstOffset = {0, 0, 0},
      .extent = {static_cast<std::uint32_t>(extent.width), static_cast<std::uint32_t>(extent.height), 1}};
}

}  // namespace

PresentImage::PresentImage(const Device& device, CommandRunner& runner, Extent extent)
    : image_(device, extent, vk::ImageUsageFlagBits::eTransferDst | vk::ImageUsageFlagBits::eTransferSrc) {
  runner.run("present image set-up", [&](const vk::raii::CommandBuffer& cb) {
    // Into the steady layout once; its (undefined) contents are never read.
    imageBarrier(cb, image_.handle(), {Stage::eTopOfPipe, {}, Layout::eUndefined}, kSteady);
  });
}

void PresentImage::recordBeforeWrite(const vk::raii::CommandBuffer& cb) const {
  // The previous frame's copy into the image (or its readback) completes before this one overwrites it.
  imageBarrier(cb, image_.handle(), kSteady, kSteady);
}

void PresentImage::recordCopyFrom(const vk::raii::CommandBuffer& cb, vk::Buffer source) const {
  recordBeforeWrite(cb);
  cb.copyBufferToImage(source, image_.handle(), Layout::eTransferDstOptimal, wholeImageRegion(extent()));
}

void PresentImage::recordCopyFrom(const vk::raii::CommandBuffer& cb, vk::Image source) const {
  recordBeforeWrite(cb);
  cb.copyImage(source, Layout::eTransferSrcOptimal, image_.handle(), Layout::eTransferDstOptimal,
               wholeImageCopy(extent()));
}

void PresentImage::recordReadback(const vk::raii::CommandBuffer& cb, vk::Buffer destination) const {
  constexpr ImageState kSource{Stage::eTransfer, Access::eTransferRead, Layout::eTransferSrcOptimal};
  // The frame copied in is complete before it is read out.
  imageBarrier(cb, image_.handle(), kSteady, kSource);
  recordImageReadback(cb, image_.handle(), Layout::eTransferSrcOptimal, extent(), destination);
  // Back to the steady layout; the next write waits for this read.
  imageBarrier(cb, image_.handle(), kSource, kSteady);
}

void recordImageReadback(const vk::raii::CommandBuffer& cb, vk::Image image, vk::ImageLayout layout, Extent extent,
                         vk::Buffer destination) {
  cb.copyImageToBuffer(image, layout, destination, wholeImageRegion(extent));
  // The copy's writes are visible to the host once the fence signals.
  bufferBarrier(cb, destination, Stage::eTransfer, Access::eTransferWrite, Stage::eHost, Access::eHostRead);
}

}  // namespace rt::gpu
