#pragma once
#include <iosfwd>
#include <memory>
#include <string>

#include "app/run_config.h"
#include "app/run_identity.h"

namespace rt {

namespace gpu {
class Context;
class Swapchain;
}  // namespace gpu
class WindowSession;

// Where the renderer's Present phase hands its frames: `upload` copies each
// frame into the device's present image, so present_ms means the same for
// every renderer; `none` leaves it where it was rendered.
struct PresentSetup {
  PresentMode mode = PresentMode::none;
  std::shared_ptr<gpu::Context> device;         // required by `upload` and by the GPU renderer
  std::shared_ptr<gpu::Swapchain> swapchain{};  // `window` only: the window's swapchain
};

// The Vulkan side of a run: the device (if any) and where Present puts frames.
struct DeviceSetup {
  PresentSetup present;
  std::string presentReason;                // for the metadata: why this present mode
  std::shared_ptr<WindowSession> window{};  // --window: the window and its events (RT_WINDOW builds)
};

// Opens the Vulkan device the run needs. --gpu, --present upload, --window,
// --device and --vk-validation need one: without it this throws
// gpu::DeviceUnavailable (exit 3; --window without a display:
// gpu::WindowUnavailable, exit 3 too). A CPU run
// without --present tries one and, failing that, presents nowhere (none)
// and writes a note to `notes`, so CPU renderers run on any machine.
DeviceSetup setUpDevice(const RunConfig& config, std::ostream& notes);

// What the run's record says of `setup`: the present mode and why, the
// device's description and whether validation is on.
RecordedDevice recordedDevice(const DeviceSetup& setup);

}  // namespace rt
