#pragma once
// What every GPU renderer keeps for its whole life, and how it records a
// frame: one command buffer for every phase, the timestamps around the
// frame's render work (gpu_ms), and Tracy's GPU zones.
#include <optional>

#include "gpu/vulkan/gpu_profiler.h"
#include "gpu/vulkan/timestamps.h"

namespace rt::gpu {

class FrameCommands {
 public:
  explicit FrameCommands(const Device& device) : runner_(device), timer_(device), profiler_(device, runner_) {}

  [[nodiscard]] CommandRunner& runner() { return runner_; }
  [[nodiscard]] const GpuProfiler& profiler() const { return profiler_; }

  // Records, submits and waits for one frame's Render phase: `prepare(cb)`
  // (resets, barriers), then `work(cb)` between the two timestamps and in
  // the Tracy GPU zone `zone`, then `finish(cb)` (copies out). Returns the
  // device time of `work` in ms; none on a queue without timestamps.
  template <typename Prepare, typename Work, typename Finish>
  std::optional<double> renderFrame(const char* zone, Prepare&& prepare, Work&& work, Finish&& finish) {
    [[maybe_unused]] const char* zoneName = zone;
    runner_.run("render", [&](const vk::raii::CommandBuffer& cb) {
      // Last frame's GPU zones have completed (its submit was waited for).
      TracyVkCollect(profiler_.context(), *cb);
      timer_.recordReset(cb);
      prepare(cb);
      {
        TracyVkZoneTransient(profiler_.context(), frameZone, *cb, zoneName, true);
        timer_.recordStart(cb);
        work(cb);
        timer_.recordEnd(cb);
      }
      finish(cb);
    });
    return timer_.readMs();
  }

 private:
  CommandRunner runner_;
  DispatchTimer timer_;
  GpuProfiler profiler_;  // after the runner, which its destructor uses
};

}  // namespace rt::gpu
