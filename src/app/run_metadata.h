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

// A run under a user-mode emulator (qemu-user running an aarch64 binary on
// x86-64, say), whose timings are not the speed of any machine.
struct Emulation {
  std::string emulator;            // the emulator's process name, or "unknown"
  std::optional<std::string> cpu;  // the emulated CPU model, where the emulator's environment names it
  std::string hostArchitecture;    // what /proc/cpuinfo describes: x86_64, aarch64 or unknown
};

// Whether this process is emulated, from what the system shows it:
// `processName` (/proc/self/comm, where qemu-user leaves its own name),
// `cpuinfo` (/proc/cpuinfo, which qemu-user 7 passes through from the host:
// another architecture than the binary's gives emulation away) and
// `emulatedCpu` (QEMU_CPU, the emulated CPU model when it was chosen that way).
std::optional<Emulation> emulationOf(std::string_view processName, std::string_view cpuinfo,
                                     std::string_view emulatedCpu);

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
