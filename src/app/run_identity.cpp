#include "app/run_identity.h"

#include <utility>

namespace rt {

RunIdentity makeRunIdentity(std::string runId, const Scene& scene, const Renderer& prepared, const RunConfig& config,
                            RecordedDevice device) {
  return {.runId = std::move(runId),
          .scene = scene.name,
          .renderer = prepared.info(),
          .options = config.options,
          .extent = config.extent,
          .present = device.present,
          .presentReason = std::move(device.presentReason),
          .device = std::move(device.device),
          .validation = device.validation};
}

}  // namespace rt
