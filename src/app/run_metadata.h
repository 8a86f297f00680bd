#pragma once
#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "app/run_config.h"
#include "app/run_identity.h"
#include "core/image.h"
#include "gpu/present/window_presentation.h"
#include "render/lane_counters.h"
#include "scene/scene.h"

namespace rt {

struct RunTimes {
  std::chrono::system_clock::time_point startedAt;
  std::chrono::system_clock::time_point finishedAt;
  double loadMs = 0.0;     // reading and checking the scene file
  double prepareMs = 0.0;  // the renderer's prepare()
};

// --window: what the window's swapchain did over the run, and whether the
// window was closed before the last frame (known once the frames are done).
struct WindowOutcome {
  gpu::SwapchainInfo swapchain;
  bool closed = false;
};

// A fresh run identifier: UTC start time plus a random suffix.
std::string makeRunId(std::chrono::system_clock::time_point startedAt);
// RFC 3339, UTC, with milliseconds: 2026-11-22T02:14:46.123Z
std::string formatRfc3339(std::chrono::system_clock::time_point t);

// The JSON sidecar: every key of the schema's run_metadata list.
// `laneCounters`: the measured frames' --counters totals (measuredCounterTotals);
// `agreement`: --agreement's comparison of frame 0 with the double reference.
nlohmann::json makeRunMetadata(const RunConfig& config, const RunIdentity& identity, const Scene& scene,
                               const RunTimes& times, const std::optional<WindowOutcome>& window = std::nullopt,
                               const std::optional<LaneCounters>& laneCounters = std::nullopt,
                               const std::optional<ImageAgreement>& agreement = std::nullopt);

}  // namespace rt
