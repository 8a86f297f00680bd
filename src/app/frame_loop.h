#pragma once
#include <exception>
#include <optional>
#include <vector>

#include "app/frame_recorder.h"
#include "app/run_config.h"
#include "core/image.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace rt {

// A --save-frame image, allocated before the frames; `filled` once the
// loop read that frame back (false where the run ended before it).
struct SavedFrame {
  Image image;
  bool filled = false;
};

struct FrameLoopResult {
  std::vector<FrameRecord> records;     // the frames that completed
  std::vector<FrameCounters> counters;  // --counters: one per record (renderer.lastCounters()); else empty
  std::vector<SavedFrame> savedFrames;  // one per config.saveFrames entry, same order
  SavedFrame agreementFrame;            // --agreement: animation frame 0 (empty image otherwise)
  std::exception_ptr failure;           // set when a frame threw; records keep what was done
};

// Where a windowed run shows its frames, as the loop sees it: asked before
// each frame whether to go on, told after each one what it took.
class LiveView {
 public:
  virtual ~LiveView() = default;
  // Handles the window's events; false once the window was closed (close
  // button, Esc, SIGINT or SIGTERM).
  virtual bool keepRunning() = 0;
  // The wait for a swapchain image inside the last Present.
  [[nodiscard]] virtual std::optional<double> lastAcquireMs() const = 0;
  // After each frame (the window's title shows the frame time).
  virtual void frameDone(const FrameRecord& record) = 0;
};

// Frames a --frames 0 run records at most (an hour at 60 frames/s); later
// frames are shown but not recorded, so recording never allocates.
inline constexpr long long kUntilClosedRecordCapacity = 216'000;

// The application loop: Update -> Render -> Present per frame, warm-up
// frames first, on a renderer that prepare() was called on for `scene`,
// config.extent and config.options (the run's identity records what
// prepare() built, so the caller prepares it before building that).
// Everything the loop touches is allocated before it. With a `view`
// (--window) it also stops when the window is closed, and with --frames 0
// only then.
FrameLoopResult runFrameLoop(Renderer& prepared, const Scene& scene, const RunConfig& config, LiveView* view = nullptr);

}  // namespace rt
