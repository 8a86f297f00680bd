#pragma once
// The Vulkan device a run uses, behind a header without Vulkan: the app and
// the CPU renderers hold it; code in src/gpu reaches the handles through
// device() (gpu/vulkan/device.h).
#include <memory>
#include <vector>

#include "gpu/vulkan/context_options.h"
#include "gpu/vulkan/device_info.h"

namespace rt::gpu {

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
