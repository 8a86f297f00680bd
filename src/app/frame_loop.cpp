#include "app/frame_loop.h"

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <tuple>
#include <utility>

#include "core/profiler.h"
#include "scene/camera.h"

namespace rt {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// Tracy zone names are the schema's phase names, the CSV's <phase>_ms columns.
constexpr const char* kUpdateZone = schema::kPhaseNames[static_cast<int>(schema::Phase::Update)].data();
constexpr const char* kRenderZone = schema::kPhaseNames[static_cast<int>(schema::Phase::Render)].data();
constexpr const char* kPresentZone = schema::kPhaseNames[static_cast<int>(schema::Phase::Present)].data();

void plotFrame([[maybe_unused]] const FrameRecord& r, [[maybe_unused]] Extent extent) {
  TracyPlot("render_ms", r.renderMs);
  if (r.gpuMs) {
    TracyPlot("gpu_ms", *r.gpuMs);
  }
  TracyPlot("Mrays/s", static_cast<double>(extent.pixelCount()) / (r.renderMs * 1e3));
}

// --counters plots. Tracy tells plots apart by the address of their name,
// so each name is one constant, used to configure and to plot.
constexpr const char* kRaysPlot = "rays";
constexpr const char* kNodeOccupancyPlot = "node lanes active %";
constexpr const char* kSphereOccupancyPlot = "sphere lanes active %";
constexpr const char* kShadeOccupancyPlot = "shade lanes active %";

void configureCounterPlots() {
  for ([[maybe_unused]] const char* name : {kNodeOccupancyPlot, kSphereOccupancyPlot, kShadeOccupancyPlot}) {
    TracyPlotConfig(name, tracy::PlotFormatType::Percentage, false, true, 0);
  }
}

// Lane occupancy, the share of vector lanes that did useful work
// (render/lane_counters.h); no point where the frame occupied no lanes.
void plotOccupancy([[maybe_unused]] const char* name, [[maybe_unused]] std::uint64_t active, std::uint64_t slots) {
  if (slots == 0) return;
  TracyPlot(name, 100.0 * static_cast<double>(active) / static_cast<double>(slots));
}

void plotCounters(const FrameCounters& counters) {
  if (!counters) return;
  TracyPlot(kRaysPlot, static_cast<std::int64_t>(counters->rays()));
  plotOccupancy(kNodeOccupancyPlot, counters->nodeLanesActive, counters->nodeLaneSlots);
  plotOccupancy(kSphereOccupancyPlot, counters->sphereLanesActive, counters->sphereLaneSlots);
  plotOccupancy(kShadeOccupancyPlot, counters->shadeLanesActive, counters->shadeLaneSlots);
}

// One frame's three phases, each timed and in its Tracy zone.
FrameRecord runOneFrame(Renderer& renderer, const Scene& scene, const RunConfig& config, const LiveView* view,
                        long long k) {
  const auto t0 = Clock::now();
  const CameraFrame camera = [&] {
    ZoneScopedN(kUpdateZone);
    return cameraAtFrame(scene.camera, k);
  }();
  const auto t1 = Clock::now();
  {
    ZoneScopedN(kRenderZone);
    renderer.render(camera);
  }
  const auto t2 = Clock::now();
  {
    ZoneScopedN(kPresentZone);
    renderer.present();
  }
  const auto t3 = Clock::now();
  return FrameRecord{.frame = k,
                     .warmup = k < config.warmupFrames,
                     .updateMs = millisecondsBetween(t0, t1),
                     .renderMs = millisecondsBetween(t1, t2),
                     .presentMs = millisecondsBetween(t2, t3),
                     .gpuMs = renderer.lastGpuMs(),
                     .acquireMs = view ? view->lastAcquireMs() : std::nullopt};
}

// Only saved frames come back to the host, after the timed phases: those
// --save-frame asks for, and frame 0 for --agreement.
void readBackAskedFrames(Renderer& renderer, const RunConfig& config, long long k, FrameLoopResult& result) {
  for (std::size_t i = 0; i < config.saveFrames.size(); ++i) {
    if (config.saveFrames[i].frame != k) continue;
    renderer.readPresented(result.savedFrames[i].image);
    result.savedFrames[i].filled = true;
  }
  if (config.agreement && k == 0) {
    renderer.readPresented(result.agreementFrame.image);
    result.agreementFrame.filled = true;
  }
}

}  // namespace

FrameLoopResult runFrameLoop(Renderer& renderer, const Scene& scene, const RunConfig& config, LiveView* view) {
  FrameLoopResult result;
  result.savedFrames.assign(config.saveFrames.size(), SavedFrame{Image(config.extent)});
  if (config.agreement) result.agreementFrame.image = Image(config.extent);
  const bool untilClosed = config.untilClosed() && view != nullptr;
  const bool counting = config.options.counters;
  FrameRecorder recorder(static_cast<std::size_t>(untilClosed ? kUntilClosedRecordCapacity : config.totalFrames()),
                         counting);
  if (counting) configureCounterPlots();

  try {
    for (long long k = 0; untilClosed || k < config.totalFrames(); ++k) {
      if (view && !view->keepRunning()) break;
      const FrameRecord record = runOneFrame(renderer, scene, config, view, k);
      // Read after the timed phases: the copy is no part of Render.
      const FrameCounters counters = counting ? renderer.lastCounters() : std::nullopt;
      recorder.record(record, counters);
      plotFrame(record, config.extent);
      plotCounters(counters);
      if (view) view->frameDone(record);
      readBackAskedFrames(renderer, config, k, result);
      FrameMark;
    }
  } catch (...) {
    result.failure = std::current_exception();
  }
  std::tie(result.records, result.counters) = std::move(recorder).take();
  return result;
}

}  // namespace rt
