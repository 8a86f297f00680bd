#pragma once
// The image a GPU renderer's shaders write a frame into, and what happens
// to it after: the Present phase (a copy into the present image, a window's
// swapchain, or nothing) and the readback of a saved or tested frame. The
// compute renderer and the ray-tracing pipeline renderer differ only in the
// pipeline stage that writes it.
#include <optional>

#include "gpu/present/present_image.h"
#include "gpu/vulkan/gpu_profiler.h"
#include "render/render_options.h"

namespace rt::gpu {

class Swapchain;

class ShaderOutput {
 public:
  // `writeStage`: the shader stage whose storage-image writes fill it.
  // Mode upload gets a present image; mode window presents into `window`.
  ShaderOutput(const Device& device, CommandRunner& runner, Extent extent, PresentMode mode,
               vk::PipelineStageFlags writeStage);

  [[nodiscard]] Extent extent() const { return image_.extent(); }
  [[nodiscard]] const DeviceImage& image() const { return image_; }

  // Records the move to the shaders' writes: the last frame's copies out of
  // the image finish first; from UNDEFINED, since every pixel is written anew.
  void recordBeforeShaderWrites(const vk::raii::CommandBuffer& cb);
  // Present: the frame into the present image (upload) or `window`'s next
  // image; nothing in mode none.
  void present(CommandRunner& runner, const GpuProfiler& profiler, Swapchain* window);
  // The presented frame (or, in mode none, the image itself) into `target`.
  void readPresented(CommandRunner& runner, Image& target);

 private:
  // Records the move from the shaders' writes to copies' reads, once per frame.
  void recordReadable(const vk::raii::CommandBuffer& cb);

  ImageState shaderWrite_;
  DeviceImage image_;
  Buffer readback_;
  std::optional<PresentImage> presentImage_;              // mode upload only
  vk::ImageLayout layout_ = vk::ImageLayout::eUndefined;  // as the last recorded commands leave it
};

}  // namespace rt::gpu
