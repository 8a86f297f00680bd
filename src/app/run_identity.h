#pragma once
// What every row of a run's CSV shares and the metadata sidecar restates:
// built once, after the renderer's prepare() and before the first frame,
// so it holds what prepare() built (the acceleration structure) and never
// changes while the frames run.
#include <optional>
#include <string>

#include "app/run_config.h"
#include "gpu/vulkan/device_info.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace rt {

// The Vulkan side of a run as its record states it; device_setup.h's
// recordedDevice() fills it, so that the record needs no header of the
// device's setup (which includes the frame loop, which includes the record).
struct RecordedDevice {
  PresentMode present = PresentMode::none;
  std::string presentReason{};
  std::optional<gpu::DeviceInfo> device{};
  bool validation = false;
};

struct RunIdentity {
  std::string runId;
  std::string scene;
  RendererInfo renderer;
  RenderOptions options;
  Extent extent;
  PresentMode present = PresentMode::none;
  std::string presentReason{};              // why this present mode (metadata)
  std::optional<gpu::DeviceInfo> device{};  // the Vulkan device used, if any
  bool validation = false;                  // Vulkan validation layer on
};

// The identity of a run of `config` on `scene` with a renderer that
// prepare() was called on, on `device`.
RunIdentity makeRunIdentity(std::string runId, const Scene& scene, const Renderer& prepared, const RunConfig& config,
                            RecordedDevice device);

}  // namespace rt
