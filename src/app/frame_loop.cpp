#include "app/frame_loop.h"

#include <chrono>
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

}  // namespace

FrameLoopResult runFrameLoop(Renderer& renderer, const Scene& scene, const RunConfig& config, LiveView* view) {
  FrameLoopResult result;
  result.savedFrames.assign(config.saveFrames.size(), SavedFrame{Image(config.extent)});
  const bool untilClosed = config.untilClosed() && view != nullptr;
  FrameRecorder recorder(static_cast<std::size_t>(untilClosed ? kUntilClosedRecordCapacity : config.totalFrames()));

  try {
    for (long long k = 0; untilClosed || k < config.totalFrames(); ++k) {
      if (view && !view->keepRunning()) break;
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

      const FrameRecord record{.frame = k,
                               .warmup = k < config.warmupFrames,
                               .updateMs = millisecondsBetween(t0, t1),
                               .renderMs = millisecondsBetween(t1, t2),
                               .presentMs = millisecondsBetween(t2, t3),
                               .gpuMs = renderer.lastGpuMs(),
                               .acquireMs = view ? view->lastAcquireMs() : std::nullopt};
      recorder.record(record);
      plotFrame(record, config.extent);
      if (view) view->frameDone(record);
      // Only saved frames come back to the host, after the timed phases.
      for (std::size_t i = 0; i < config.saveFrames.size(); ++i) {
        if (config.saveFrames[i].frame != k) continue;
        renderer.readPresented(result.savedFrames[i].image);
        result.savedFrames[i].filled = true;
      }
      FrameMark;
    }
  } catch (...) {
    result.failure = std::current_exception();
  }
  result.records = std::move(recorder).takeRecords();
  return result;
}

}  // namespace rt
