#pragma once
// The ray-tracing pipeline of the gpu_rt renderer: the ray-generation
// shader (shaders/raytrace.rgen, with or without the hit reorder), the miss
// shader, and one procedural hit group (sphere.rint's intersection,
// sphere.rchit's closest hit); its shader binding table on the device; and
// the descriptor set that binds the top-level structure, the spheres and the
// output image.
#include "gpu/compute/gpu_layout.h"
#include "gpu/vulkan/descriptor_set.h"
#include "gpu/vulkan/resources.h"

namespace rt::gpu {

// The raygen shader's specialization constants (the algorithm, the bounce
// exit, maxDepth: as the compute renderer's), and which raygen is built.
struct RayTracingVariant {
  std::uint32_t twoPass;     // VkBool32
  std::uint32_t bounceExit;  // VkBool32
  std::int32_t maxDepth;
  bool reorder = false;  // --gpu-rt-reorder hit: the raygen built with RT_REORDER
};

class RayTracingPipeline {
 public:
  RayTracingPipeline(const Device& device, CommandRunner& runner, const RayTracingVariant& variant);

  [[nodiscard]] const vk::raii::DescriptorSetLayout& setLayout() const { return setLayout_; }
  // Binds the pipeline and `set`, pushes the frame's constants and traces
  // one ray-generation invocation per pixel of `extent`.
  void recordTrace(const vk::raii::CommandBuffer& cb, vk::DescriptorSet set, const FrameConstants& constants,
                   Extent extent) const;

 private:
  vk::raii::DescriptorSetLayout setLayout_;
  vk::raii::PipelineLayout layout_;
  vk::raii::Pipeline pipeline_;
  Buffer bindingTable_;
  vk::StridedDeviceAddressRegionKHR raygenRegion_, missRegion_, hitRegion_;
};

// The descriptor set of one scene and image.
class RayTracingBindings {
 public:
  RayTracingBindings(const Device& device, const RayTracingPipeline& pipeline, vk::AccelerationStructureKHR topLevel,
                     vk::Buffer spheres, const DeviceImage& output);
  [[nodiscard]] vk::DescriptorSet set() const { return set_.handle(); }

 private:
  PooledDescriptorSet set_;
};

}  // namespace rt::gpu
