#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace rt {

struct RunIdentity;

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

// Holds every frame's record in storage sized before the frame loop, so
// recording allocates nothing and does no I/O; the CSV is written after.
class FrameRecorder {
 public:
  explicit FrameRecorder(std::size_t capacity) { records_.reserve(capacity); }

  void record(const FrameRecord& r) {
    if (records_.size() < records_.capacity()) records_.push_back(r);  // never grows: no allocation
  }
  [[nodiscard]] std::span<const FrameRecord> records() const { return records_; }
  // The records, handed over without a copy once the frames are done.
  [[nodiscard]] std::vector<FrameRecord> takeRecords() && { return std::move(records_); }

 private:
  std::vector<FrameRecord> records_;
};

// The CSV text: header row from the schema, then one row per record.
std::string formatFrameCsv(const RunIdentity& identity, std::span<const FrameRecord> records);

}  // namespace rt
