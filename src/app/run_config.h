#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "render/render_options.h"

namespace rt {

// --save-frame K:FILE: frame K (counted from the first warm-up frame) to a PNG.
struct SaveFrameRequest {
  long long frame = 0;
  std::filesystem::path file;
};

// Everything one run of the binary was asked to do.
struct RunConfig {
  RendererKind renderer = RendererKind::sequential;
  std::filesystem::path scenePath = "scenes/default.json";
  Extent extent{800, 600};
  int warmupFrames = 3;
  int measuredFrames = 20;
  RenderOptions options;      // default: stage "optimized"
  ParallelSettings parallel;  // --threads, --lanes, --grain, --partition
  std::optional<std::filesystem::path> csvPath;
  std::optional<std::filesystem::path> metaPath;
  std::vector<SaveFrameRequest> saveFrames;
  // --agreement: frame 0's image is compared with the double-precision
  // reference after the frames, into the metadata (docs/render-model.md section 8).
  bool agreement = false;
  bool quiet = false;
  bool tracyWait = false;  // wait for a Tracy viewer before the first frame
  std::vector<std::string> commandLine;
  // The Vulkan device and the Present phase (docs/gpu.md).
  std::optional<PresentMode> present;  // --present; nullopt: upload when a device opens, else none
  std::string device;                  // --device INDEX|NAME-SUBSTRING; empty: the default choice
  bool listDevices = false;            // --list-devices: print them and exit
  bool vkValidation = false;           // --vk-validation: validation layer on, messages fail the run
  // The live window (docs/window.md): --window is --present window.
  schema::SwapchainPresentMode swapchainPresentMode = schema::SwapchainPresentMode::fifo;  // --present-mode

  [[nodiscard]] long long totalFrames() const { return static_cast<long long>(warmupFrames) + measuredFrames; }
  [[nodiscard]] bool windowed() const { return present == PresentMode::window; }
  // --window --frames 0: frames go on until the window is closed.
  [[nodiscard]] bool untilClosed() const { return windowed() && measuredFrames == 0; }
};

// Where the metadata sidecar goes: --meta, else beside the CSV as NAME.meta.json
// (none where the CSV goes to a device or FIFO, such as /dev/null).
std::optional<std::filesystem::path> metadataPathFor(const RunConfig& config);

// From this many spheres up, brute force is slow enough that a run with
// --accel none says so before it starts.
inline constexpr std::size_t kBruteForceNoticeSpheres = 5000;

// What a brute-force run over `sphereCount` spheres will cost and which
// option is faster, said at once instead of leaving the user to wait in
// silence; empty below kBruteForceNoticeSpheres or with a structure.
std::optional<std::string> bruteForceNotice(const RunConfig& config, std::size_t sphereCount);

}  // namespace rt
