#pragma once
#include "gpu/vulkan/resources.h"

namespace rt::gpu {

// The windowless stand-in for the swapchain image: every renderer's Present
// phase copies its frame into it, and it is read back to the host only when
// a frame is saved or tested. Between commands it stays in
// TRANSFER_DST_OPTIMAL, the layout it is written in every frame.
class PresentImage {
 public:
  PresentImage(const Device& device, CommandRunner& runner, Extent extent);

  [[nodiscard]] Extent extent() const { return image_.extent(); }
  // Records a copy from `source`, tightly packed RGBA8 rows the host wrote
  // before the submission (the CPU renderers' upload).
  void recordCopyFrom(const vk::raii::CommandBuffer& cb, vk::Buffer source) const;
  // Records a copy from `source`, an image in TRANSFER_SRC_OPTIMAL whose
  // writes were made available to transfer reads (the GPU renderer's output).
  void recordCopyFrom(const vk::raii::CommandBuffer& cb, vk::Image source) const;
  // Records a copy of the image into `destination`, visible to host reads after the fence.
  void recordReadback(const vk::raii::CommandBuffer& cb, vk::Buffer destination) const;

 private:
  void recordBeforeWrite(const vk::raii::CommandBuffer& cb) const;
  DeviceImage image_;
};

// Records a copy of `image` (in `layout`) into `destination` and the
// barrier that makes it visible to host reads after the fence.
void recordImageReadback(const vk::raii::CommandBuffer& cb, vk::Image image, vk::ImageLayout layout, Extent extent,
                         vk::Buffer destination);

}  // namespace rt::gpu
