#include "app/run_summary.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace rt {
namespace {

// The median of an odd count is the middle value; of an even count, the
// mean of the two middle ones (as pandas and the report compute it).
TimingSummary summarize(std::vector<double> values) {
  if (values.empty()) return {};
  std::ranges::sort(values);
  const std::size_t n = values.size();
  const double median = n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return {median, values.front(), values.back()};
}

template <typename... Args>
std::string format(const char* pattern, Args... args) {
  char line[512];
  std::snprintf(line, sizeof line, pattern, args...);
  return line;
}

}  // namespace

RunSummary summarizeRun(Extent extent, std::span<const FrameRecord> records) {
  std::vector<double> render, update, present, gpu;
  for (const auto& r : records) {
    if (r.warmup) continue;
    render.push_back(r.renderMs);
    update.push_back(r.updateMs);
    present.push_back(r.presentMs);
    if (r.gpuMs) gpu.push_back(*r.gpuMs);
  }
  RunSummary s;
  s.measuredFrames = render.size();
  s.renderMs = summarize(std::move(render));
  s.updateMs = summarize(std::move(update));
  s.presentMs = summarize(std::move(present));
  if (!gpu.empty()) s.gpuMs = summarize(std::move(gpu));
  if (s.renderMs.median > 0.0)
    s.primaryRaysPerSecond = static_cast<double>(extent.pixelCount()) / (s.renderMs.median * 1e-3);
  return s;
}

std::string formatRunSummary(const RunIdentity& id, const RunSummary& s) {
  std::string text =
      format("%s  %s  %dx%d  %s  early_exit=%s  %zu frames\n", std::string(nameOf(id.renderer.kind)).c_str(),
             id.scene.c_str(), id.extent.width, id.extent.height, std::string(nameOf(id.options.algorithm)).c_str(),
             id.options.earlyExits.toString().c_str(), s.measuredFrames);
  if (!id.renderer.simdTarget.empty() || id.renderer.grain) {
    text += format("  threads=%d  lanes=%d  simd_target=%s\n", id.renderer.threads, id.renderer.lanes,
                   id.renderer.simdTarget.empty() ? "-" : id.renderer.simdTarget.c_str());
  }
  text += format("  render_ms  median %.3f  min %.3f  max %.3f   (%.2f Mprimary-rays/s)\n", s.renderMs.median,
                 s.renderMs.min, s.renderMs.max, s.primaryRaysPerSecond * 1e-6);
  text += format("  update_ms  median %.4f   present_ms median %.3f  (present %s)\n", s.updateMs.median,
                 s.presentMs.median, std::string(nameOf(id.present)).c_str());
  if (s.gpuMs)
    text += format("  gpu_ms     median %.3f  min %.3f  max %.3f\n", s.gpuMs->median, s.gpuMs->min, s.gpuMs->max);
  if (id.device) text += format("  device     %s (%s)\n", id.device->name.c_str(), id.device->driverInfo.c_str());
  return text;
}

}  // namespace rt
