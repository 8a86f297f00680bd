#pragma once
#include <optional>
#include <span>
#include <string>

#include "app/frame_recorder.h"
#include "app/run_identity.h"

namespace rt {

// Median, minimum and maximum of one timing over the measured frames.
struct TimingSummary {
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
};

// The console summary of a run: its measured frames (warm-up excluded).
struct RunSummary {
  std::size_t measuredFrames = 0;
  TimingSummary renderMs, updateMs, presentMs;
  std::optional<TimingSummary> gpuMs;  // where the renderer measured device time
  double primaryRaysPerSecond = 0.0;   // pixels / median render time
};

RunSummary summarizeRun(Extent extent, std::span<const FrameRecord> records);

// The lines printed after a run (not with --quiet).
std::string formatRunSummary(const RunIdentity& identity, const RunSummary& summary);

}  // namespace rt
