#pragma once
#include <cstdint>
#include <span>

#include "gpu/compute/gpu_layout.h"
#include "gpu/vulkan/descriptor_set.h"
#include "gpu/vulkan/resources.h"
#include "render/render_options.h"

namespace rt::gpu {

// The SPIR-V of shaders/raytrace.comp, compiled at build time and linked
// into the binary: nothing is looked up on disk at run time. One build per
// precision: f16 computes the render model in float16_t (needs shaderFloat16).
std::span<const std::uint32_t> raytraceSpirv(Precision precision);

// Workgroups needed to cover `pixels` with groups of `groupSize`: rounded
// up, the shader skips the overhang.
constexpr std::uint32_t workgroupCount(int pixels, int groupSize) {
  return static_cast<std::uint32_t>((pixels + groupSize - 1) / groupSize);
}

// The compute pipeline of one variant (the precision's SPIR-V; algorithm,
// bounce exit, maxDepth, the BVH and the counters as specialization
// constants), with its set and pipeline layouts.
class RaytracePipeline {
 public:
  RaytracePipeline(const Device& device, Precision precision, const SpecializationConstants& constants);

  [[nodiscard]] const vk::raii::DescriptorSetLayout& setLayout() const { return setLayout_; }
  // Binds the pipeline and `set`, and pushes this frame's constants.
  void recordBind(const vk::raii::CommandBuffer& cb, vk::DescriptorSet set, const FrameConstants& constants) const;

 private:
  vk::raii::DescriptorSetLayout setLayout_;
  vk::raii::PipelineLayout layout_;
  vk::raii::Pipeline pipeline_;
};

// The storage buffers the shader reads and writes. Slots a variant does not
// use name the sphere buffer: a descriptor must point at a live buffer, and
// that variant never touches them.
struct SceneBuffers {
  vk::Buffer spheres;
  vk::Buffer bvhNodes;
  vk::Buffer bvhOrder;
  vk::Buffer wideNodes;
  vk::Buffer wideIndex;
  vk::Buffer counters;
  vk::Buffer leafSpheres;
  vk::Buffer gridCells;
  vk::Buffer loopGuard;

  // Every slot naming `spheres`, for the others to be set.
  static SceneBuffers allSpheres(vk::Buffer spheres) {
    return {spheres, spheres, spheres, spheres, spheres, spheres, spheres, spheres, spheres};
  }
};

// The descriptor set that binds the scene's buffers and an output image.
class RaytraceBindings {
 public:
  RaytraceBindings(const Device& device, const RaytracePipeline& pipeline, const SceneBuffers& buffers,
                   const DeviceImage& output);
  [[nodiscard]] vk::DescriptorSet set() const { return set_.handle(); }

 private:
  PooledDescriptorSet set_;
};

}  // namespace rt::gpu
