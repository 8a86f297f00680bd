#pragma once
// The serial scheduling strategy (sequential, simd_only): the calling thread
// walks the image in bands of rows. Each band is one Tracy zone named like
// the oneTBB chunks ("rows"), so the profiler shows every renderer's work
// split the same way without a zone per row.
#include <algorithm>
#include <optional>

#include "core/image.h"
#include "core/profiler.h"
#include "render/cpu_contracts.h"
#include "render/render_options.h"

namespace rt {

class SerialScheduler {
 public:
  static constexpr Scheduler kId = Scheduler::serial;
  static constexpr int kRowsPerBand = 16;

  SerialScheduler() = default;
  explicit SerialScheduler(const ParallelSettings& /*settings*/) {}

  [[nodiscard]] int threads() const { return 1; }
  [[nodiscard]] std::optional<int> grain() const { return std::nullopt; }
  [[nodiscard]] std::optional<Partition> partition() const { return std::nullopt; }

  // Calls body(slot, y, x0, x1) for every row of the image, whole rows, in
  // order, on the calling thread (slot 0). Whole rows satisfy any alignment.
  template <typename Body>
  void forEachSpan(Extent extent, int /*alignment*/, const Body& body) const {
    for (int first = 0; first < extent.height; first += kRowsPerBand) {
      ZoneScopedN("rows");
      const int last = std::min(extent.height, first + kRowsPerBand);
      for (int y = first; y < last; ++y) body(0, y, 0, extent.width);
    }
  }
};
static_assert(SpanScheduler<SerialScheduler>);

}  // namespace rt
