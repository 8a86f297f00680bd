#pragma once
// Owning wrappers for the few kinds of Vulkan resources the renderers use,
// and the command-buffer runner every phase submits through.
#include <cstddef>
#include <span>
#include <string_view>

#include "core/image.h"
#include "gpu/vulkan/device.h"

namespace rt::gpu {

// What a buffer's memory is for, which decides its memory type.
enum class MemoryUse {
  deviceLocal,  // read by shaders every frame: filled once through a staging copy
  upload,       // written by the host through a persistent mapping
  readback,     // read by the host through a persistent mapping
};

// A buffer with its own memory, mapped for its whole life when the host uses it.
// With eShaderDeviceAddress usage its memory is allocated for device
// addresses (acceleration structures and their inputs, shader binding tables).
class Buffer {
 public:
  Buffer(const Device& device, vk::DeviceSize size, vk::BufferUsageFlags usage, MemoryUse use);

  [[nodiscard]] vk::Buffer handle() const { return *buffer_; }
  // Only for buffers made with eShaderDeviceAddress usage.
  [[nodiscard]] vk::DeviceAddress deviceAddress() const;
  [[nodiscard]] vk::DeviceSize size() const { return size_; }
  // The mapping; empty for deviceLocal buffers.
  [[nodiscard]] std::span<std::byte> mapped() const { return mapped_; }
  // Make host writes visible to the device (a no-op on coherent memory).
  void flushHostWrites() const;
  // Make device writes visible to the host, after the fence (a no-op on coherent memory).
  void invalidateForHost() const;

 private:
  const Device* device_;
  vk::DeviceSize size_;
  vk::raii::Buffer buffer_;
  vk::raii::DeviceMemory memory_ = nullptr;
  std::span<std::byte> mapped_;
  bool coherent_ = true;
};

// A 2D RGBA8 image in device-local memory, optimal tiling.
class DeviceImage {
 public:
  DeviceImage(const Device& device, Extent extent, vk::ImageUsageFlags usage);

  [[nodiscard]] vk::Image handle() const { return *image_; }
  [[nodiscard]] Extent extent() const { return extent_; }
  // A view for descriptor use; only for images created with eStorage usage.
  [[nodiscard]] vk::ImageView view() const { return *view_; }

 private:
  Extent extent_;
  vk::raii::Image image_;
  vk::raii::DeviceMemory memory_ = nullptr;
  vk::raii::ImageView view_ = nullptr;
};

inline constexpr vk::Format kFrameFormat = vk::Format::eR8G8B8A8Unorm;  // Rgba8

// One side of a barrier: which pipeline stage, which access, which layout.
struct ImageState {
  vk::PipelineStageFlags stage;
  vk::AccessFlags access;
  vk::ImageLayout layout;
};

void imageBarrier(const vk::raii::CommandBuffer& cb, vk::Image image, ImageState from, ImageState to);
void bufferBarrier(const vk::raii::CommandBuffer& cb, vk::Buffer buffer, vk::PipelineStageFlags fromStage,
                   vk::AccessFlags fromAccess, vk::PipelineStageFlags toStage, vk::AccessFlags toAccess);

// The whole image as one tightly packed region (rows of width * 4 bytes,
// row 0 at the top, as rt::Image stores them).
vk::BufferImageCopy wholeImageRegion(Extent extent);
vk::DeviceSize frameBytes(Extent extent);

// Copies the host-visible `buffer` (after invalidateForHost) into `target`.
void copyToImage(const Buffer& buffer, Image& target);

// The reverse: a frame's pixels into the host-visible `buffer`, flushed for
// the device (host writes before a submission need no barrier).
void copyFromFrame(std::span<const Rgba8> frame, const Buffer& buffer);

// One command buffer and one fence: record, submit, wait. Every phase waits
// for its own work, so nothing is in flight when a phase returns and one
// command buffer serves all of them.
class CommandRunner {
 public:
  explicit CommandRunner(const Device& device);

  // Records through `record(commandBuffer)`, submits, and waits. `what`
  // names the work in errors ("render", "present").
  template <typename Record>
  void run(std::string_view what, Record&& record) {
    begin();
    record(commandBuffer_);
    submitAndWait(what);
  }

  // The command buffer, reset and not recording, for a user that records
  // and submits it by itself (Tracy's GPU context set-up).
  [[nodiscard]] const vk::raii::CommandBuffer& idleCommandBuffer();

 private:
  void begin();
  void submitAndWait(std::string_view what);

  const Device& device_;
  vk::raii::CommandPool pool_;
  vk::raii::CommandBuffer commandBuffer_ = nullptr;
  vk::raii::Fence fence_;
};

// `bytes` in a new device-local buffer of `usage` (plus eTransferDst), through
// a staging buffer; a barrier makes the copy visible to `readStage`'s
// `readAccess`. Waits for the copy; the staging buffer goes on return.
Buffer uploadToDevice(const Device& device, CommandRunner& runner, std::span<const std::byte> bytes,
                      vk::BufferUsageFlags usage, vk::PipelineStageFlags readStage, vk::AccessFlags readAccess);

// Runs `body`, turning a Vulkan failure into a DeviceError that says what was being done.
template <typename Body>
decltype(auto) translateVulkanErrors(std::string_view what, Body&& body);

// The message of such a DeviceError: the work, the VkResult, and what it usually means.
std::string describeVulkanFailure(std::string_view what, vk::Result result, std::string_view detail);

template <typename Body>
decltype(auto) translateVulkanErrors(std::string_view what, Body&& body) {
  try {
    return body();
  } catch (const vk::SystemError& e) {
    throw DeviceError(describeVulkanFailure(what, static_cast<vk::Result>(e.code().value()), e.what()));
  }
}

}  // namespace rt::gpu
