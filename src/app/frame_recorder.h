#pragma once
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"
#include "gpu/present/window_presentation.h"
#include "gpu/vulkan/device_info.h"
#include "render/renderer.h"

namespace rt {

// One frame's timings; the CSV's per-frame columns.
struct FrameRecord {
  long long frame = 0;
  bool warmup = false;
  double updateMs = 0.0;
  double renderMs = 0.0;
  double presentMs = 0.0;
  std::optional<double> gpuMs;
  std::optional<double> acquireMs;  // --window: the part of presentMs spent waiting for a swapchain image
};

// What every row of a run shares.
struct RunIdentity {
  std::string runId;
  std::string scene;
  RendererInfo renderer;
  RenderOptions options;
  Extent extent;
  PresentMode present = PresentMode::none;
  std::string presentReason{};            // why this present mode (metadata)
  std::optional<gpu::DeviceInfo> device{};  // the Vulkan device used, if any
  bool validation = false;                // Vulkan validation layer on
  std::optional<gpu::SwapchainInfo> swapchain{};  // --window: the window's swapchain
  bool windowClosed = false;              // --window: closed before the last frame (or --frames 0)
};

// Holds every frame's record in storage sized before the frame loop, so
// recording allocates nothing and does no I/O; the CSV is written after.
class FrameRecorder {
 public:
  explicit FrameRecorder(std::size_t capacity) { records_.reserve(capacity); }

  void record(const FrameRecord& r) {
    if (records_.size() < records_.capacity()) records_.push_back(r);  // never grows: no allocation
  }
  [[nodiscard]] std::span<const FrameRecord> records() const { return records_; }

 private:
  std::vector<FrameRecord> records_;
};

// The CSV text: header row from the schema, then one row per record.
std::string formatFrameCsv(const RunIdentity& identity, std::span<const FrameRecord> records);

}  // namespace rt
