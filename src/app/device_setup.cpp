#include "app/device_setup.h"

#include <ostream>

#include "gpu/vulkan/context.h"
#if RT_WINDOW
#include "app/window_session.h"
#endif

namespace rt {
namespace {

std::string firstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

DeviceSetup setUpDevice(const RunConfig& config, std::ostream& notes) {
  // Asking for a device by name or for validation is asking for a device too.
  const bool gpuRenderer = config.renderer == RendererKind::gpu || config.renderer == RendererKind::gpu_rt;
  const bool required =
      gpuRenderer || config.present == PresentMode::upload || !config.device.empty() || config.vkValidation;
  if (!required && config.present == PresentMode::none) return {{PresentMode::none, nullptr}, "--present none"};

  const bool rayTracing = config.renderer == RendererKind::gpu_rt;
  const gpu::ContextOptions options{
      .deviceSelector = config.device,
      .validation = config.vkValidation,
      .rayTracing = rayTracing,
      .invocationReorder = rayTracing && config.options.gpuRtReorder == GpuRtReorder::hit,
      .shaderFloat16 = config.renderer == RendererKind::gpu && config.options.precision == Precision::f16};
#if RT_WINDOW
  if (config.windowed()) {
    auto window = WindowSession::open(config, options);
    return {{PresentMode::window, window->context(), window->swapchain()}, "--window", window};
  }
#endif
  if (required) {
    const PresentMode mode = config.present.value_or(PresentMode::upload);
    return {{mode, gpu::Context::open(options)}, config.present ? "--present" : "default: a Vulkan device is open"};
  }
  try {
    return {{PresentMode::upload, gpu::Context::open(options)}, "default: a Vulkan device is open"};
  } catch (const gpu::DeviceUnavailable& e) {
    const std::string reason = "default: no Vulkan device (" + firstLine(e.what()) + ")";
    if (!config.quiet)
      notes << "raytracer: note: no Vulkan device, frames are not presented (--present none): " << firstLine(e.what())
            << "\n";
    return {{PresentMode::none, nullptr}, reason};
  }
}

RecordedDevice recordedDevice(const DeviceSetup& setup) {
  const gpu::Context* device = setup.present.device.get();
  return {.present = setup.present.mode,
          .presentReason = setup.presentReason,
          .device = device ? std::optional(device->info()) : std::nullopt,
          .validation = device && device->validationEnabled()};
}

}  // namespace rt
