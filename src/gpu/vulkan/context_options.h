#pragma once
// What opening a device is asked for, and the validation messages counted
// since: shared by the Context (gpu/vulkan/context.h) and the Device behind
// it (gpu/vulkan/device.h), so that neither header includes the other.
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace rt::gpu {

// Where the Vulkan loader is looked up by default; a build may name a full
// path (Nix, where dlopen does not search system directories).
#ifndef RT_VULKAN_LOADER
#define RT_VULKAN_LOADER "libvulkan.so.1"
#endif

struct ContextOptions {
  std::string deviceSelector{};  // --device; empty: the default choice
  // VK_LAYER_KHRONOS_validation with synchronization validation, and a
  // debug messenger that prints and counts every warning and error.
  bool validation = false;
  std::string loaderLibrary = RT_VULKAN_LOADER;
  // A window's presentation (--window): the instance extensions its surface
  // needs (from GLFW) are enabled, and the device gets VK_KHR_swapchain.
  // Empty for windowless runs, whose instance has no surface extension.
  std::vector<std::string> surfaceExtensions{};
  // The ray-tracing pipeline renderer (gpu_rt): the device must offer
  // VK_KHR_acceleration_structure and VK_KHR_ray_tracing_pipeline, which
  // are enabled with buffer device addresses; invocationReorder also asks
  // for VK_NV_ray_tracing_invocation_reorder. A device without them is
  // refused (DeviceUnavailable), as a missing device is.
  bool rayTracing = false;
  bool invocationReorder = false;
  // The compute renderer in half precision (--precision f16): the device
  // must offer shaderFloat16 (Vulkan 1.2), which is enabled; a device
  // without it is refused with FeatureUnavailable.
  bool shaderFloat16 = false;
  [[nodiscard]] bool presents() const { return !surfaceExtensions.empty(); }
};

struct ValidationCounts {
  std::uint32_t warnings = 0;
  std::uint32_t errors = 0;
  [[nodiscard]] std::uint32_t total() const { return warnings + errors; }
};

// What the debug messenger has reported. Shared, so that it can be read
// after the device is gone: vkDestroyDevice reports objects left alive.
class ValidationCounter {
 public:
  void add(bool error) { (error ? errors_ : warnings_).fetch_add(1, std::memory_order_relaxed); }
  [[nodiscard]] ValidationCounts counts() const {
    return {warnings_.load(std::memory_order_relaxed), errors_.load(std::memory_order_relaxed)};
  }

 private:
  std::atomic<std::uint32_t> warnings_{0};
  std::atomic<std::uint32_t> errors_{0};
};

}  // namespace rt::gpu
