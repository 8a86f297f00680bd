#pragma once
// The Vulkan device a run uses, behind a header without Vulkan: the app and
// the CPU renderers hold it; code in src/gpu reaches the handles through
// device() (gpu/vulkan/device.h).
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gpu/vulkan/device_info.h"

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

class Device;

// One open device: instance (surface extensions only for a window), the chosen physical
// device, a logical device with one compute-capable queue. Shared by the
// renderer and whoever reports on it, so it outlives every resource made
// from it whatever the destruction order of its owners.
class Context {
 public:
  // Throws DeviceUnavailable (no loader, no device, --device matches
  // nothing, validation asked for but not installed).
  static std::shared_ptr<Context> open(const ContextOptions& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  [[nodiscard]] const DeviceInfo& info() const;
  [[nodiscard]] bool validationEnabled() const;
  // Warnings and errors reported through the debug messenger so far.
  [[nodiscard]] ValidationCounts validationMessages() const;
  // The counter itself, which outlives the context (null without validation).
  [[nodiscard]] std::shared_ptr<const ValidationCounter> validationCounter() const;
  [[nodiscard]] Device& device() const { return *device_; }

  // Only open() can make the key: a Context always holds an open device.
  class Key {
    friend class Context;
    Key() = default;
  };
  Context(Key, std::unique_ptr<Device> device);

 private:
  std::unique_ptr<Device> device_;
};

// Every physical device the loader reports, described (--list-devices).
// Throws DeviceUnavailable when there is no loader or instance.
std::vector<DeviceInfo> listDevices(const ContextOptions& options);

}  // namespace rt::gpu
