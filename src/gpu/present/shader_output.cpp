#include "gpu/present/shader_output.h"

#include <stdexcept>

#include "gpu/present/swapchain.h"

namespace rt::gpu {
namespace {

constexpr ImageState kTransferRead{vk::PipelineStageFlagBits::eTransfer, vk::AccessFlagBits::eTransferRead,
                                   vk::ImageLayout::eTransferSrcOptimal};

}  // namespace

ShaderOutput::ShaderOutput(const Device& device, CommandRunner& runner, Extent extent, PresentMode mode,
                           vk::PipelineStageFlags writeStage)
    : shaderWrite_{writeStage, vk::AccessFlagBits::eShaderWrite, vk::ImageLayout::eGeneral},
      image_(device, extent, vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc),
      readback_(device, frameBytes(extent), vk::BufferUsageFlagBits::eTransferDst, MemoryUse::readback) {
  if (mode == PresentMode::upload) presentImage_.emplace(device, runner, extent);
}

void ShaderOutput::recordBeforeShaderWrites(const vk::raii::CommandBuffer& cb) {
  imageBarrier(cb, image_.handle(), {vk::PipelineStageFlagBits::eTransfer, {}, vk::ImageLayout::eUndefined},
               shaderWrite_);
  layout_ = shaderWrite_.layout;
}

void ShaderOutput::recordReadable(const vk::raii::CommandBuffer& cb) {
  if (layout_ == kTransferRead.layout) return;
  if (layout_ != shaderWrite_.layout) throw std::logic_error("GPU renderer: no frame rendered yet");
  // The shader's writes are complete and visible before a copy reads them.
  imageBarrier(cb, image_.handle(), shaderWrite_, kTransferRead);
  layout_ = kTransferRead.layout;
}

void ShaderOutput::present(CommandRunner& runner, [[maybe_unused]] const GpuProfiler& profiler, Swapchain* window) {
  if (window) {
    translateVulkanErrors("present", [&] {
      // Not waited for: the next frame's barrier waits for this blit's reads.
      window->present(image_.handle(), extent(),
                      [&](const vk::raii::CommandBuffer& cb, std::uint32_t) { recordReadable(cb); });
    });
    return;
  }
  if (!presentImage_) return;  // mode none: the frame stays in the storage image
  translateVulkanErrors("present", [&] {
    runner.run("present", [&](const vk::raii::CommandBuffer& cb) {
      TracyVkZone(profiler.context(), *cb, "present copy");
      recordReadable(cb);
      presentImage_->recordCopyFrom(cb, image_.handle());
    });
  });
}

void ShaderOutput::readPresented(CommandRunner& runner, Image& target) {
  if (target.extent() != extent()) throw std::logic_error("readPresented: target extent differs from the frame's");
  translateVulkanErrors("frame readback", [&] {
    runner.run("frame readback", [&](const vk::raii::CommandBuffer& cb) {
      if (presentImage_) {
        presentImage_->recordReadback(cb, readback_.handle());
      } else {
        recordReadable(cb);
        recordImageReadback(cb, image_.handle(), kTransferRead.layout, extent(), readback_.handle());
      }
    });
    copyToImage(readback_, target);
  });
}

}  // namespace rt::gpu
