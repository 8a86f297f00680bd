// raytracer: loads a scene, runs the frame loop with the chosen renderer,
// then writes the per-frame CSV, the metadata sidecar and saved frames.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <iostream>
#include <vector>

#include "app/cli.h"
#include "app/frame_loop.h"
#include "app/run_metadata.h"
#include "core/atomic_file.h"
#include "core/profiler.h"
#include "render/renderer_factory.h"
#include "scene/scene_loader.h"

namespace {

constexpr int kExitRuntimeError = 1;

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::ranges::sort(values);
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void printSummary(const rt::RunIdentity& id, std::span<const rt::FrameRecord> records) {
  std::vector<double> render, update, present;
  for (const auto& r : records) {
    if (r.warmup) continue;
    render.push_back(r.renderMs);
    update.push_back(r.updateMs);
    present.push_back(r.presentMs);
  }
  const double renderMedian = median(render);
  const double mrays = renderMedian > 0.0 ? static_cast<double>(id.extent.pixelCount()) / (renderMedian * 1e3) : 0.0;
  std::printf("%s  %s  %dx%d  %s  early_exit=%s  %zu frames\n", std::string(rt::nameOf(id.renderer.kind)).c_str(),
              id.scene.c_str(), id.extent.width, id.extent.height, std::string(rt::nameOf(id.options.algorithm)).c_str(),
              id.options.earlyExits.toString().c_str(), render.size());
  if (!id.renderer.simdTarget.empty() || id.renderer.grain) {
    std::printf("  threads=%d  lanes=%d  simd_target=%s\n", id.renderer.threads, id.renderer.lanes,
                id.renderer.simdTarget.empty() ? "-" : id.renderer.simdTarget.c_str());
  }
  std::printf("  render_ms  median %.3f  min %.3f  max %.3f   (%.2f Mprimary-rays/s)\n", renderMedian,
              *std::ranges::min_element(render), *std::ranges::max_element(render), mrays);
  std::printf("  update_ms  median %.4f   present_ms median %.3f\n", median(update), median(present));
}

void writeOutputs(const rt::RunConfig& config, const rt::RunIdentity& identity, const rt::Scene& scene,
                  const rt::FrameLoopResult& result, const rt::RunTimes& times) {
  if (config.csvPath) rt::writeFileAtomically(*config.csvPath, rt::formatFrameCsv(identity, result.records));
  if (const auto meta = rt::metadataPathFor(config)) {
    rt::writeFileAtomically(*meta, rt::makeRunMetadata(config, identity, scene, times).dump(2) + "\n");
  }
  for (std::size_t i = 0; i < config.saveFrames.size(); ++i) {
    const bool rendered = std::ranges::any_of(result.records, [&](const auto& r) { return r.frame == config.saveFrames[i].frame; });
    if (rendered) rt::writePng(result.savedFrames[i], config.saveFrames[i].file);
  }
}

// Blocks until a Tracy viewer is connected, so the capture holds every frame.
void waitForTracyViewer() {
  const char* port = std::getenv("TRACY_PORT");
  std::fprintf(stderr, "raytracer: waiting for a Tracy viewer on 127.0.0.1:%s ...\n", port != nullptr ? port : "8086");
  while (!TracyIsConnected) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

std::string describeRun(const rt::RunIdentity& id, const rt::RunConfig& config) {
  return std::string(rt::nameOf(id.renderer.kind)) + " scene=" + id.scene + " " + std::to_string(id.extent.width) + "x" +
         std::to_string(id.extent.height) + " threads=" + std::to_string(id.renderer.threads) +
         " lanes=" + std::to_string(id.renderer.lanes) + " target=" + id.renderer.simdTarget +
         " algorithm=" + std::string(rt::nameOf(id.options.algorithm)) + " early_exit=" + id.options.earlyExits.toString() +
         " frames=" + std::to_string(config.warmupFrames) + "+" + std::to_string(config.measuredFrames);
}

int run(const rt::RunConfig& config) {
  const rt::Scene scene = rt::loadScene(config.scenePath);
  auto renderer = rt::makeRenderer(config.renderer, config.parallel);

  rt::RunTimes times{std::chrono::system_clock::now(), {}};
  const rt::RunIdentity identity{rt::makeRunId(times.startedAt), scene.name, renderer->info(), config.options,
                                 config.extent};
  if (config.tracyWait) waitForTracyViewer();
  [[maybe_unused]] const std::string description = describeRun(identity, config);
  TracyMessage(description.data(), description.size());
  const rt::FrameLoopResult result = rt::runFrameLoop(*renderer, scene, config);
  times.finishedAt = std::chrono::system_clock::now();

  // Frames that completed are written even when a later one failed.
  writeOutputs(config, identity, scene, result, times);
  if (result.failure) std::rethrow_exception(result.failure);
  if (!config.quiet) printSummary(identity, result.records);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  auto parsed = rt::parseCommandLine(argc, argv);
  if (auto* exit = std::get_if<rt::CliExit>(&parsed)) {
    std::cout << exit->output;
    std::cerr << exit->error;
    return exit->code;
  }
  try {
    return run(std::get<rt::RunConfig>(parsed));
  } catch (const rt::SceneError& e) {
    std::cerr << "raytracer: invalid scene: " << e.what() << "\n";
    return rt::kExitBadInput;
  } catch (const rt::RendererUnavailable& e) {
    std::cerr << "raytracer: " << e.what() << "\n";
    return rt::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "raytracer: error: " << e.what() << "\n";
    return kExitRuntimeError;
  }
}
