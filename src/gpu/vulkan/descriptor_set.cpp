#include "gpu/vulkan/descriptor_set.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace rt::gpu {
namespace {

// A pool for one set of `bindings`: as many descriptors of each type as they hold.
vk::raii::DescriptorPool createPool(const Device& device, std::span<const vk::DescriptorSetLayoutBinding> bindings) {
  std::vector<vk::DescriptorPoolSize> sizes;
  for (const vk::DescriptorSetLayoutBinding& binding : bindings) {
    const auto same = std::ranges::find(sizes, binding.descriptorType, &vk::DescriptorPoolSize::type);
    if (same == sizes.end()) {
      sizes.push_back({.type = binding.descriptorType, .descriptorCount = binding.descriptorCount});
    } else {
      same->descriptorCount += binding.descriptorCount;
    }
  }
  // FreeDescriptorSet: the RAII set frees itself before the pool goes.
  return {device.logical(), vk::DescriptorPoolCreateInfo{.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                         .maxSets = 1,
                                                         .poolSizeCount = static_cast<std::uint32_t>(sizes.size()),
                                                         .pPoolSizes = sizes.data()}};
}

}  // namespace

PooledDescriptorSet::PooledDescriptorSet(const Device& device, vk::DescriptorSetLayout layout,
                                         std::span<const vk::DescriptorSetLayoutBinding> bindings)
    : pool_(createPool(device, bindings)) {
  vk::raii::DescriptorSets sets(
      device.logical(),
      vk::DescriptorSetAllocateInfo{.descriptorPool = *pool_, .descriptorSetCount = 1, .pSetLayouts = &layout});
  set_ = std::move(sets.front());
}

void PooledDescriptorSet::write(const Device& device, std::span<vk::WriteDescriptorSet> writes) const {
  for (vk::WriteDescriptorSet& write : writes) write.dstSet = *set_;
  device.logical().updateDescriptorSets(writes, {});
}

}  // namespace rt::gpu
