#pragma once
// The one descriptor set each GPU renderer binds per scene, and the pool
// made for it alone: the compute renderer's and the ray-tracing pipeline
// renderer's bindings differ only in what they write into it.
#include <span>

#include "gpu/vulkan/device.h"

namespace rt::gpu {

class PooledDescriptorSet {
 public:
  // A set of `layout`, made of `bindings`; the pool holds just as many
  // descriptors of each type.
  PooledDescriptorSet(const Device& device, vk::DescriptorSetLayout layout,
                      std::span<const vk::DescriptorSetLayoutBinding> bindings);

  [[nodiscard]] vk::DescriptorSet handle() const { return *set_; }
  // Points each of `writes` at this set, then updates it.
  void write(const Device& device, std::span<vk::WriteDescriptorSet> writes) const;

 private:
  vk::raii::DescriptorPool pool_;
  vk::raii::DescriptorSet set_ = nullptr;  // after the pool: freed before it goes
};

}  // namespace rt::gpu
