#pragma once
#include <iosfwd>
#include <string>

#include <memory>

#include "app/run_config.h"

namespace rt {

namespace gpu {
class Context;
}

// Where the renderer's Present phase hands its frames: `upload` copies each
// frame into the device's present image, so present_ms means the same for
// every renderer; `none` leaves it where it was rendered.
struct PresentSetup {
  PresentMode mode = PresentMode::none;
  std::shared_ptr<gpu::Context> device;  // required by `upload` and by the GPU renderer
};

// The Vulkan side of a run: the device (if any) and where Present puts frames.
struct DeviceSetup {
  PresentSetup present;
  std::string presentReason;  // for the metadata: why this present mode
};

// Opens the Vulkan device the run needs. --gpu, --present upload, --device
// and --vk-validation need one: without it this throws
// gpu::DeviceUnavailable (exit 3). A CPU run
// without --present tries one and, failing that, presents nowhere (none)
// and writes a note to `notes`, so CPU renderers run on any machine.
DeviceSetup setUpDevice(const RunConfig& config, std::ostream& notes);

}  // namespace rt
