#include "gpu/vulkan/context.h"

#include "gpu/vulkan/device.h"

namespace rt::gpu {

// Context =====================================================================

std::shared_ptr<Context> Context::open(const ContextOptions& options) {
  try {
    return std::make_shared<Context>(Key{}, std::make_unique<Device>(options));
  } catch (const vk::SystemError& e) {
    throw DeviceUnavailable(std::string("cannot open a Vulkan device: ") + e.what() + loaderEnvironmentNote());
  }
}

Context::Context(Key, std::unique_ptr<Device> device) : device_(std::move(device)) {}
Context::~Context() = default;

const DeviceInfo& Context::info() const { return device_->info(); }
bool Context::validationEnabled() const { return device_->instance().validationEnabled(); }
ValidationCounts Context::validationMessages() const { return device_->instance().validationMessages(); }
std::shared_ptr<const ValidationCounter> Context::validationCounter() const {
  return validationEnabled() ? device_->instance().validationCounter() : nullptr;
}

std::vector<DeviceInfo> listDevices(const ContextOptions& options) {
  try {
    const Instance instance(options);
    std::vector<DeviceInfo> infos;
    for (const auto& c : describePhysicalDevices(instance)) infos.push_back(c.info);
    return infos;
  } catch (const vk::SystemError& e) {
    throw DeviceUnavailable(std::string("cannot list Vulkan devices: ") + e.what() + loaderEnvironmentNote());
  }
}

}  // namespace rt::gpu
