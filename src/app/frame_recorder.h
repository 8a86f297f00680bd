#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "render/lane_counters.h"

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

// One frame's --counters tallies: nullopt where the renderer reported none.
// Kept beside the FrameRecords, not in them: a LaneCounters is some 600
// bytes, and a run without --counters (a --window run records up to
// kUntilClosedRecordCapacity frames) reserves nothing for them.
using FrameCounters = std::optional<LaneCounters>;

// Holds every frame's record (and, when `counting`, its counters) in storage
// sized before the frame loop, so recording allocates nothing and does no
// I/O; the CSV is written after.
class FrameRecorder {
 public:
  explicit FrameRecorder(std::size_t capacity, bool counting = false) : counting_(counting) {
    records_.reserve(capacity);
    if (counting_) counters_.reserve(capacity);
  }

  // `counters` is kept only by a counting recorder.
  void record(const FrameRecord& r, const FrameCounters& counters = std::nullopt) {
    if (records_.size() == records_.capacity()) return;  // never grows: no allocation
    records_.push_back(r);
    if (counting_) counters_.push_back(counters);
  }
  [[nodiscard]] std::span<const FrameRecord> records() const { return records_; }
  // One per record when counting, else empty.
  [[nodiscard]] std::span<const FrameCounters> counters() const { return counters_; }
  // The records and counters, handed over without a copy once the frames are done.
  [[nodiscard]] std::pair<std::vector<FrameRecord>, std::vector<FrameCounters>> take() && {
    return {std::move(records_), std::move(counters_)};
  }

 private:
  bool counting_;
  std::vector<FrameRecord> records_;
  std::vector<FrameCounters> counters_;
};

// The CSV text: header row from the schema, then one row per record.
// `counters` is empty (the counter columns stay empty) or one per record.
std::string formatFrameCsv(const RunIdentity& identity, std::span<const FrameRecord> records,
                           std::span<const FrameCounters> counters = {});

// The counters of the measured (non-warm-up) frames summed field by field;
// nullopt where no measured frame reported any: the metadata's lane_counters
// (schema run_metadata). `counters` as for formatFrameCsv.
std::optional<LaneCounters> measuredCounterTotals(std::span<const FrameRecord> records,
                                                  std::span<const FrameCounters> counters);

}  // namespace rt
