#include "app/run_identity.h"

#include <utility>

#include "app/device_setup.h"
#include "gpu/vulkan/context.h"

namespace rt {

RunIdentity makeRunIdentity(std::string runId, const Scene& scene, const Renderer& prepared, const RunConfig& config,
                            const DeviceSetup& setup) {
  const gpu::Context* device = setup.present.device.get();
  return {.runId = std::move(runId),
          .scene = scene.name,
          .renderer = prepared.info(),
          .options = config.options,
          .extent = config.extent,
          .present = setup.present.mode,
          .presentReason = setup.presentReason,
          .device = device ? std::optional(device->info()) : std::nullopt,
          .validation = device && device->validationEnabled()};
}

}  // namespace rt
