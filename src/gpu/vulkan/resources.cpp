#include "gpu/vulkan/resources.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace rt::gpu {
namespace {

using MemoryProperty = vk::MemoryPropertyFlagBits;

// Longer than any frame this program renders, even at -O0 on lavapipe; a
// GPU that has not finished by then is hung, and the run should say so.
constexpr std::chrono::nanoseconds kFenceTimeout = std::chrono::seconds(120);

struct MemoryChoice {
  vk::MemoryPropertyFlags required;
  vk::MemoryPropertyFlags preferred;
};

MemoryChoice memoryFor(MemoryUse use) {
  switch (use) {
    case MemoryUse::deviceLocal: return {MemoryProperty::eDeviceLocal, {}};
    case MemoryUse::upload: return {MemoryProperty::eHostVisible, MemoryProperty::eHostCoherent};
    // Cached: the host reads every byte; reads from uncached memory are slow.
    case MemoryUse::readback:
      return {MemoryProperty::eHostVisible, MemoryProperty::eHostCached | MemoryProperty::eHostCoherent};
  }
  return {MemoryProperty::eDeviceLocal, {}};
}

vk::raii::DeviceMemory allocate(const Device& device, const vk::MemoryRequirements& requirements,
                                std::uint32_t typeIndex, bool deviceAddress = false) {
  const vk::MemoryAllocateFlagsInfo addressable{.flags = vk::MemoryAllocateFlagBits::eDeviceAddress};
  return vk::raii::DeviceMemory(device.logical(),
                                vk::MemoryAllocateInfo{.pNext = deviceAddress ? &addressable : nullptr,
                                                       .allocationSize = requirements.size,
                                                       .memoryTypeIndex = typeIndex});
}

}  // namespace

// Buffer ======================================================================

Buffer::Buffer(const Device& device, vk::DeviceSize size, vk::BufferUsageFlags usage, MemoryUse use)
    : device_(&device), size_(size), buffer_(device.logical(), vk::BufferCreateInfo{.size = size, .usage = usage}) {
  const vk::MemoryRequirements requirements = buffer_.getMemoryRequirements();
  const MemoryChoice choice = memoryFor(use);
  const std::uint32_t type = device.memoryTypeIndex(requirements.memoryTypeBits, choice.required, choice.preferred);
  memory_ =
      allocate(device, requirements, type, static_cast<bool>(usage & vk::BufferUsageFlagBits::eShaderDeviceAddress));
  buffer_.bindMemory(*memory_, 0);
  if (use != MemoryUse::deviceLocal) {
    // Mapped once for the buffer's life; freeing the memory unmaps it.
    mapped_ = {static_cast<std::byte*>(memory_.mapMemory(0, size_)), static_cast<std::size_t>(size_)};
    coherent_ = static_cast<bool>(device.memoryTypeProperties(type) & MemoryProperty::eHostCoherent);
  }
}

vk::DeviceAddress Buffer::deviceAddress() const {
  return device_->logical().getBufferAddress(vk::BufferDeviceAddressInfo{.buffer = *buffer_});
}

Buffer uploadToDevice(const Device& device, CommandRunner& runner, std::span<const std::byte> bytes,
                      vk::BufferUsageFlags usage, vk::PipelineStageFlags readStage, vk::AccessFlags readAccess) {
  Buffer target(device, bytes.size(), usage | vk::BufferUsageFlagBits::eTransferDst, MemoryUse::deviceLocal);
  const Buffer staging(device, bytes.size(), vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::upload);
  std::memcpy(staging.mapped().data(), bytes.data(), bytes.size());
  staging.flushHostWrites();
  runner.run("upload", [&](const vk::raii::CommandBuffer& cb) {
    cb.copyBuffer(staging.handle(), target.handle(), vk::BufferCopy{.size = bytes.size()});
    bufferBarrier(cb, target.handle(), vk::PipelineStageFlagBits::eTransfer, vk::AccessFlagBits::eTransferWrite,
                  readStage, readAccess);
  });
  return target;
}

void Buffer::flushHostWrites() const {
  if (coherent_) return;
  device_->logical().flushMappedMemoryRanges(
      vk::MappedMemoryRange{.memory = *memory_, .offset = 0, .size = VK_WHOLE_SIZE});
}

void Buffer::invalidateForHost() const {
  if (coherent_) return;
  device_->logical().invalidateMappedMemoryRanges(
      vk::MappedMemoryRange{.memory = *memory_, .offset = 0, .size = VK_WHOLE_SIZE});
}

// DeviceImage =================================================================

DeviceImage::DeviceImage(const Device& device, Extent extent, vk::ImageUsageFlags usage)
    : extent_(extent),
      image_(device.logical(), vk::ImageCreateInfo{.imageType = vk::ImageType::e2D,
                                                   .format = kFrameFormat,
                                                   .extent = {static_cast<std::uint32_t>(extent.width),
                                                              static_cast<std::uint32_t>(extent.height), 1},
                                                   .mipLevels = 1,
                                                   .arrayLayers = 1,
                                                   .samples = vk::SampleCountFlagBits::e1,
                                                   .tiling = vk::ImageTiling::eOptimal,
                                                   .usage = usage,
                                                   .sharingMode = vk::SharingMode::eExclusive,
                                                   .initialLayout = vk::ImageLayout::eUndefined}) {
  const vk::MemoryRequirements requirements = image_.getMemoryRequirements();
  memory_ = allocate(device, requirements,
                     device.memoryTypeIndex(requirements.memoryTypeBits, MemoryProperty::eDeviceLocal, {}));
  image_.bindMemory(*memory_, 0);
  if (usage & vk::ImageUsageFlagBits::eStorage) {
    view_ = vk::raii::ImageView(
        device.logical(), vk::ImageViewCreateInfo{.image = *image_,
                                                  .viewType = vk::ImageViewType::e2D,
                                                  .format = kFrameFormat,
                                                  .subresourceRange = {vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1}});
  }
}

// Barriers and copies =========================================================

void imageBarrier(const vk::raii::CommandBuffer& cb, vk::Image image, ImageState from, ImageState to) {
  const vk::ImageMemoryBarrier barrier{.srcAccessMask = from.access,
                                       .dstAccessMask = to.access,
                                       .oldLayout = from.layout,
                                       .newLayout = to.layout,
                                       .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                       .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                       .image = image,
                                       .subresourceRange = {vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1}};
  cb.pipelineBarrier(from.stage, to.stage, {}, {}, {}, barrier);
}

void bufferBarrier(const vk::raii::CommandBuffer& cb, vk::Buffer buffer, vk::PipelineStageFlags fromStage,
                   vk::AccessFlags fromAccess, vk::PipelineStageFlags toStage, vk::AccessFlags toAccess) {
  const vk::BufferMemoryBarrier barrier{.srcAccessMask = fromAccess,
                                        .dstAccessMask = toAccess,
                                        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                        .buffer = buffer,
                                        .offset = 0,
                                        .size = VK_WHOLE_SIZE};
  cb.pipelineBarrier(fromStage, toStage, {}, {}, barrier, {});
}

vk::BufferImageCopy wholeImageRegion(Extent extent) {
  return vk::BufferImageCopy{
      .bufferOffset = 0,
      .bufferRowLength = 0,  // 0: tightly packed rows
      .bufferImageHeight = 0,
      .imageSubresource = {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
      .imageOffset = {0, 0, 0},
      .imageExtent = {static_cast<std::uint32_t>(extent.width), static_cast<std::uint32_t>(extent.height), 1}};
}

vk::DeviceSize frameBytes(Extent extent) { return extent.pixelCount() * sizeof(Rgba8); }

void copyToImage(const Buffer& buffer, Image& target) {
  buffer.invalidateForHost();
  const std::span<const std::byte> bytes = buffer.mapped().first(frameBytes(target.extent()));
  std::memcpy(target.pixels().data(), bytes.data(), bytes.size());
}

void copyFromFrame(std::span<const Rgba8> frame, const Buffer& buffer) {
  std::memcpy(buffer.mapped().data(), frame.data(), frame.size_bytes());
  buffer.flushHostWrites();
}

// CommandRunner ===============================================================

CommandRunner::CommandRunner(const Device& device)
    : device_(device),
      pool_(device.logical(), vk::CommandPoolCreateInfo{.flags = vk::CommandPoolCreateFlagBits::eResetCommandBuffer,
                                                        .queueFamilyIndex = device.queueFamily()}),
      fence_(device.logical(), vk::FenceCreateInfo{}) {
  vk::raii::CommandBuffers buffers(
      device.logical(), vk::CommandBufferAllocateInfo{
                            .commandPool = *pool_, .level = vk::CommandBufferLevel::ePrimary, .commandBufferCount = 1});
  commandBuffer_ = std::move(buffers.front());
}

const vk::raii::CommandBuffer& CommandRunner::idleCommandBuffer() {
  commandBuffer_.reset();
  return commandBuffer_;
}

void CommandRunner::begin() {
  commandBuffer_.reset();
  commandBuffer_.begin(vk::CommandBufferBeginInfo{.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
}

void CommandRunner::submitAndWait(std::string_view what) {
  commandBuffer_.end();
  const vk::CommandBuffer cb = *commandBuffer_;
  device_.queue().submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &cb}, *fence_);
  const vk::Result waited =
      device_.logical().waitForFences(*fence_, VK_TRUE, static_cast<std::uint64_t>(kFenceTimeout.count()));
  if (waited == vk::Result::eTimeout) {
    // Lavapipe renders on the CPU: there a long wait is a frame too large for
    // it (the ray-tracing pipeline renderer's is linear in the spheres), not a hang.
    const bool lavapipe = device_.info().driverName == "llvmpipe";
    throw DeviceError(
        std::string(what) + ": the Vulkan device did not finish within " +
        std::to_string(std::chrono::duration_cast<std::chrono::seconds>(kFenceTimeout).count()) + " s" +
        (lavapipe ? " (lavapipe renders on the CPU: a smaller image or scene, or --gpu, may finish)" : " (hung GPU?)"));
  }
  device_.logical().resetFences(*fence_);
}

// Errors ======================================================================

std::string describeVulkanFailure(std::string_view what, vk::Result result, std::string_view detail) {
  std::string message = "Vulkan failure during " + std::string(what) + ": " + vk::to_string(result);
  switch (result) {
    case vk::Result::eErrorDeviceLost:
      message += " (the device was lost: a driver reset, a hung or removed GPU)";
      break;
    case vk::Result::eErrorOutOfDeviceMemory:
      message += " (out of device memory: try a smaller --width/--height)";
      break;
    case vk::Result::eErrorOutOfHostMemory: message += " (out of host memory)"; break;
    default: break;
  }
  if (!detail.empty()) message += " [" + std::string(detail) + "]";
  return message;
}

}  // namespace rt::gpu
