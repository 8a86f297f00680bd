// raytracer: loads a scene, runs the frame loop with the chosen renderer,
// then writes the per-frame CSV, the metadata sidecar and saved frames.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <thread>
#include <vector>

#include "app/cli.h"
#include "app/device_setup.h"
#include "app/frame_loop.h"
#include "app/program_main.h"
#include "app/renderer_factory.h"
#include "app/run_identity.h"
#include "app/run_metadata.h"
#include "app/run_summary.h"
#include "app/stage_progress.h"
#include "core/atomic_file.h"
#include "core/profiler.h"
#include "gpu/present/window_presentation.h"
#include "gpu/vulkan/context.h"
#include "render/scalar/double_reference.h"
#if RT_WINDOW
#include "app/window_session.h"
#endif
#include "scene/scene_loader.h"

namespace {

void writeOutputs(const rt::RunConfig& config, const rt::RunIdentity& identity, const rt::Scene& scene,
                  const rt::FrameLoopResult& result, const rt::RunTimes& times,
                  const std::optional<rt::WindowOutcome>& window, const std::optional<rt::ImageAgreement>& agreement) {
  if (config.csvPath) {
    rt::writeFileAtomically(*config.csvPath, rt::formatFrameCsv(identity, result.records, result.counters));
  }
  if (const auto meta = rt::metadataPathFor(config)) {
    const auto laneCounters = rt::measuredCounterTotals(result.records, result.counters);
    rt::writeFileAtomically(
        *meta, rt::makeRunMetadata(config, identity, scene, times, window, laneCounters, agreement).dump(2) + "\n");
  }
  for (std::size_t i = 0; i < config.saveFrames.size(); ++i) {
    if (result.savedFrames[i].filled) rt::writePng(result.savedFrames[i].image, config.saveFrames[i].file);
  }
}

// Where the lines of slow start-up stages go: stderr, nowhere with --quiet.
std::ostream* progressStream(const rt::RunConfig& config) { return config.quiet ? nullptr : &std::cerr; }

// --agreement: frame 0 against the double-precision reference (docs/render-model.md
// section 8), after the timed frames; nothing where the run ended before frame 0.
std::optional<rt::ImageAgreement> agreementWithReference(const rt::RunConfig& config, const rt::Scene& scene,
                                                         const rt::SavedFrame& frame) {
  if (!config.agreement || !frame.filled) return std::nullopt;
  rt::StageProgress stage("comparing frame 0 with the double-precision reference", progressStream(config));
  const rt::Image reference =
      rt::renderDoubleReference(scene, rt::cameraAtFrame(scene.camera, 0), config.extent, config.options);
  const rt::ImageAgreement agreement = rt::compareImages(frame.image, reference);
  stage.finish();
  return agreement;
}

// "scenes/x.json (125 MB)"; a pipe's size is not known before it is read.
std::string describeSceneFile(const std::filesystem::path& path) {
  std::error_code ec;
  const auto bytes = std::filesystem::is_regular_file(path, ec) ? std::filesystem::file_size(path, ec) : 0;
  if (ec || bytes == 0) return path.string();
  return path.string() + " (" + std::to_string((bytes + 500'000) / 1'000'000) + " MB)";
}

// Blocks until a Tracy viewer is connected, so the capture holds every frame.
void waitForTracyViewer() {
  const char* port = std::getenv("TRACY_PORT");
  std::fprintf(stderr, "raytracer: waiting for a Tracy viewer on 127.0.0.1:%s ...\n", port != nullptr ? port : "8086");
  while (!TracyIsConnected) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

// --gpu-bvh auto's choice, said once before the frames: what each candidate
// took in the probe and which one runs (the metadata's gpu_walk_probe).
std::string describeWalkProbe(const rt::RunIdentity& id) {
  const rt::GpuWalkProbe& probe = *id.renderer.gpuWalkProbe;
  std::string text = "--gpu-bvh auto: probe frames of " + std::to_string(probe.extent.width) + "x" +
                     std::to_string(probe.extent.height) + " took (gpu_ms)";
  for (const auto& [candidate, ms] : probe.gpuMs) {
    char figure[32];
    std::snprintf(figure, sizeof figure, " %.3f", ms);
    text += " " + candidate + figure;
  }
  return text + "; runs " +
         (id.renderer.gpuBvh ? std::string(rt::nameOf(*id.renderer.gpuBvh)) : "brute force (accel none)");
}

std::string describeRun(const rt::RunIdentity& id, const rt::RunConfig& config) {
  return std::string(rt::nameOf(id.renderer.kind)) + " scene=" + id.scene + " " + std::to_string(id.extent.width) +
         "x" + std::to_string(id.extent.height) + " threads=" + std::to_string(id.renderer.threads) +
         " lanes=" + std::to_string(id.renderer.lanes) + " target=" + id.renderer.simdTarget +
         " algorithm=" + std::string(rt::nameOf(id.options.algorithm)) +
         " early_exit=" + id.options.earlyExits.toString() + " accel=" + std::string(rt::nameOf(id.options.accel)) +
         (id.renderer.traversal ? " traversal=" + std::string(rt::nameOf(*id.renderer.traversal)) : "") +
         (id.renderer.gpuBvh ? " gpu_bvh=" + std::string(rt::nameOf(*id.renderer.gpuBvh)) : "") +
         (id.renderer.gpuSchedule ? " gpu_schedule=" + std::string(rt::nameOf(*id.renderer.gpuSchedule)) : "") +
         (id.renderer.gpuPath ? " gpu_path=" + std::string(rt::nameOf(*id.renderer.gpuPath)) : "") +
         (id.renderer.gpuRtReorder ? " gpu_rt_reorder=" + std::string(rt::nameOf(*id.renderer.gpuRtReorder)) : "") +
         (id.renderer.precision != rt::Precision::f32 ? " precision=" + std::string(rt::nameOf(id.renderer.precision))
                                                      : "") +
         (id.options.counters ? " counters" : "") + " frames=" + std::to_string(config.warmupFrames) + "+" +
         std::to_string(config.measuredFrames) + " present=" + std::string(rt::nameOf(id.present)) +
         (id.device ? " device=" + id.device->name : "");
}

// --list-devices: every device the loader reports, the default choice marked.
int listDevices(const rt::RunConfig& config) {
  const auto devices = rt::gpu::listDevices({.validation = config.vkValidation});
  std::optional<std::size_t> chosen;
  try {
    chosen = rt::gpu::chooseDevice(devices, config.device);
  } catch (const rt::gpu::DeviceUnavailable&) {
    if (devices.empty()) throw;  // nothing to list: the "no device" exit
  }
  std::cout << "Vulkan devices (index, name, type, driver, API version; * = the device a run uses):\n"
            << rt::gpu::formatDeviceList(devices, chosen);
  return 0;
}

// With --vk-validation, any message the layer reported fails the run.
int validationVerdict(const rt::gpu::ValidationCounter* validation) {
  if (!validation || validation->counts().total() == 0) return 0;
  const rt::gpu::ValidationCounts counts = validation->counts();
  std::cerr << "raytracer: Vulkan validation reported " << counts.errors << " error(s) and " << counts.warnings
            << " warning(s)\n";
  return rt::kExitRuntimeError;
}

// Opens the device, runs the frame loop, writes the outputs. Returns the
// validation counter of the device used (null without --vk-validation).
std::shared_ptr<const rt::gpu::ValidationCounter> renderAndWrite(const rt::RunConfig& config, const rt::Scene& scene,
                                                                 double loadMs) {
  const rt::DeviceSetup setup = rt::setUpDevice(config, std::cerr);
  auto renderer = rt::makeRenderer(config.renderer, config.parallel, setup.present);

  rt::RunTimes times{std::chrono::system_clock::now(), {}, loadMs, 0.0};
  if (config.tracyWait) waitForTracyViewer();
  if (const auto notice = rt::bruteForceNotice(config, scene.spheres.size()); notice && !config.quiet) {
    std::cerr << "raytracer: " << *notice << "\n";
  }
  {
    rt::StageProgress stage("preparing " + std::string(rt::nameOf(config.renderer)) + " (" +
                                std::to_string(scene.spheres.size()) + " spheres, accel " +
                                std::string(rt::nameOf(config.options.accel)) + ")",
                            progressStream(config));
    renderer->prepare(scene, config.extent, config.options);
    times.prepareMs = stage.finish();
  }
  const rt::RunIdentity identity =
      rt::makeRunIdentity(rt::makeRunId(times.startedAt), scene, *renderer, config, rt::recordedDevice(setup));
  if (identity.renderer.gpuWalkProbe && !config.quiet)
    std::cerr << "raytracer: " << describeWalkProbe(identity) << "\n";
  [[maybe_unused]] const std::string description = describeRun(identity, config);
  TracyMessage(description.data(), description.size());
  rt::LiveView* view = nullptr;
#if RT_WINDOW
  view = setup.window.get();
#endif
  const rt::FrameLoopResult result = rt::runFrameLoop(*renderer, scene, config, view);
  times.finishedAt = std::chrono::system_clock::now();
  std::optional<rt::WindowOutcome> window;
#if RT_WINDOW
  if (setup.window) window = rt::WindowOutcome{setup.window->swapchainInfo(), setup.window->closed()};
#endif

  // Frames that completed are written even when a later one failed; a run
  // whose first frame failed (lavapipe's loop limit, a lost device) writes
  // nothing, as one refused before its frames.
  if (result.failure && result.records.empty()) std::rethrow_exception(result.failure);
  const auto agreement = agreementWithReference(config, scene, result.agreementFrame);
  writeOutputs(config, identity, scene, result, times, window, agreement);
  if (result.failure) std::rethrow_exception(result.failure);
  if (!config.quiet) std::cout << rt::formatRunSummary(identity, rt::summarizeRun(identity.extent, result.records));
  return setup.present.device ? setup.present.device->validationCounter() : nullptr;
}  // the renderer and the device go here: the layer reports objects left alive

int run(const rt::RunConfig& config) {
  if (config.listDevices) return listDevices(config);
  rt::StageProgress stage("loading " + describeSceneFile(config.scenePath), progressStream(config));
  const rt::Scene scene = rt::loadScene(config.scenePath);
  const double loadMs = stage.finish();
  const auto validation = renderAndWrite(config, scene, loadMs);
  return validationVerdict(validation.get());
}

}  // namespace

int main(int argc, char** argv) { return rt::runProgram("raytracer", argc, argv, run); }
