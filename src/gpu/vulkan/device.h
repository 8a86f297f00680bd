#pragma once
// The Vulkan objects behind gpu::Context, for the code in src/gpu and the
// GPU renderer. Members are declared in creation order, so that C++
// destroys them in the reverse order Vulkan requires.
#include <memory>
#include <string>
#include <vector>

#include "gpu/vulkan/context_options.h"
#include "gpu/vulkan/device_info.h"
#include "gpu/vulkan/vk.h"

namespace rt::gpu {

// The Vulkan loader, opened with dlopen: a machine without it gets a clear
// error instead of a binary that does not start.
class LoaderLibrary {
 public:
  explicit LoaderLibrary(const std::string& name);
  [[nodiscard]] PFN_vkGetInstanceProcAddr getInstanceProcAddr() const { return getInstanceProcAddr_; }

 private:
  struct Closer {
    void operator()(void* handle) const;
  };
  std::unique_ptr<void, Closer> handle_;
  PFN_vkGetInstanceProcAddr getInstanceProcAddr_ = nullptr;
};

// A Vulkan instance without surface extensions, with the validation layer
// and a counting debug messenger when asked for.
class Instance {
 public:
  explicit Instance(const ContextOptions& options);
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  [[nodiscard]] const vk::raii::Instance& get() const { return instance_; }
  [[nodiscard]] bool validationEnabled() const { return validation_; }
  [[nodiscard]] ValidationCounts validationMessages() const { return counter_->counts(); }
  [[nodiscard]] const std::shared_ptr<ValidationCounter>& validationCounter() const { return counter_; }
  [[nodiscard]] PFN_vkGetInstanceProcAddr getInstanceProcAddr() const { return loader_.getInstanceProcAddr(); }

 private:
  bool validation_;
  LoaderLibrary loader_;
  vk::raii::Context context_;
  // Vulkan holds its address until the messenger and instance are gone.
  std::shared_ptr<ValidationCounter> counter_ = std::make_shared<ValidationCounter>();
  vk::raii::Instance instance_ = nullptr;
  vk::raii::DebugUtilsMessengerEXT messenger_ = nullptr;
};

// A physical device with its description and the queue family the renderer
// would use.
struct PhysicalDeviceChoice {
  vk::raii::PhysicalDevice physical;
  DeviceInfo info;
  std::uint32_t queueFamily;
};

std::vector<PhysicalDeviceChoice> describePhysicalDevices(const Instance& instance);

// The loader's driver-selection variables that are set, as a note for "no
// device" errors (empty when none is): a stray one is the usual reason a
// device is missing.
std::string loaderEnvironmentNote();

// The chosen physical device, a logical device and its one compute queue.
class Device {
 public:
  explicit Device(const ContextOptions& options);
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  [[nodiscard]] const Instance& instance() const { return instance_; }
  [[nodiscard]] const DeviceInfo& info() const { return info_; }
  [[nodiscard]] const vk::raii::PhysicalDevice& physical() const { return physical_; }
  [[nodiscard]] const vk::raii::Device& logical() const { return device_; }
  [[nodiscard]] const vk::raii::Queue& queue() const { return queue_; }
  [[nodiscard]] std::uint32_t queueFamily() const { return queueFamily_; }
  // Whether the device was created with shaderFloat16 enabled (ContextOptions::shaderFloat16).
  [[nodiscard]] bool shaderFloat16() const { return shaderFloat16_; }
  // Whether the device was created with VK_EXT_pipeline_robustness, so that a
  // pipeline may turn off the bounds tests of its storage-buffer accesses
  // (the compute renderer does: docs/render-model.md section 3). Without it
  // the driver decides, as before.
  [[nodiscard]] bool pipelineRobustness() const { return pipelineRobustness_; }

  // A memory type allowed by `typeBits` with every `required` property;
  // among those, one that also has the `preferred` ones when there is one.
  [[nodiscard]] std::uint32_t memoryTypeIndex(std::uint32_t typeBits, vk::MemoryPropertyFlags required,
                                              vk::MemoryPropertyFlags preferred) const;
  [[nodiscard]] vk::MemoryPropertyFlags memoryTypeProperties(std::uint32_t typeIndex) const;

 private:
  Instance instance_;
  DeviceInfo info_;
  vk::raii::PhysicalDevice physical_ = nullptr;
  std::uint32_t queueFamily_ = 0;
  vk::PhysicalDeviceMemoryProperties memory_;
  vk::raii::Device device_ = nullptr;
  vk::raii::Queue queue_ = nullptr;
  bool shaderFloat16_ = false;
  bool pipelineRobustness_ = false;
};

}  // namespace rt::gpu
