#pragma once
#include <iosfwd>
#include <string>

#include "app/run_config.h"
#include "render/present_setup.h"

namespace rt {

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
