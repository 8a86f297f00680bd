#include "app/run_identity.h"

#include <utility>

namespace rt {

namespace {

// The options as they ran: --accel auto and --gpu-bvh auto as what
// prepare() settled on, the structure and walk it kept or brute force (the
// CSV and the metadata never say auto).
RenderOptions optionsAsRun(const RenderOptions& asked, const RendererInfo& prepared) {
  RenderOptions options = asked;
  if (options.accel == Accel::auto_) options.accel = prepared.accelStructure ? Accel::bvh : Accel::none;
  if (options.gpuBvh == GpuBvh::auto_) options.gpuBvh = prepared.gpuBvh.value_or(RenderOptions{}.gpuBvh);
  return options;
}

}  // namespace

RunIdentity makeRunIdentity(std::string runId, const Scene& scene, const Renderer& prepared, const RunConfig& config,
                            RecordedDevice device) {
  RendererInfo info = prepared.info();
  RenderOptions options = optionsAsRun(config.options, info);
  return {.runId = std::move(runId),
          .scene = scene.name,
          .renderer = std::move(info),
          .options = std::move(options),
          .extent = config.extent,
          .present = device.present,
          .presentReason = std::move(device.presentReason),
          .device = std::move(device.device),
          .validation = device.validation};
}

}  // namespace rt
