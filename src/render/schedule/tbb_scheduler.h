#pragma once
// The oneTBB scheduling strategy (simd_tbb, tbb_only): parallel_for over
// the image's rows (the thesis' scheme) or over row x column tiles.
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/blocked_range2d.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <optional>

#include "core/image.h"
#include "core/profiler.h"
#include "render/cpu_contracts.h"
#include "render/render_options.h"

namespace rt {

// Owns the thread limit for as long as the renderer lives (a temporary
// global_control would lift it again at once) and splits frames into spans
// of one row each. A span's first pixel is a multiple of `alignment` (the
// SIMD packet width), so packets never straddle two spans. Threads write
// disjoint runs of the working buffer (whole rows, or 256-byte tile rows),
// so two of them can share at most the one cache line at a span's edge.
class TbbScheduler {
 public:
  static constexpr Scheduler kId = Scheduler::tbb;

  // Throws std::invalid_argument for threads < 0 or grain < 1.
  TbbScheduler(int threads, int grain, Partition partition);
  explicit TbbScheduler(const ParallelSettings& settings)
      : TbbScheduler(settings.threads, settings.grain, settings.partition) {}

  [[nodiscard]] int threads() const { return threads_; }
  [[nodiscard]] std::optional<int> grain() const { return grain_; }
  [[nodiscard]] std::optional<Partition> partition() const { return partition_; }

  // Calls body(slot, y, x0, x1) once for every span of the image, possibly
  // in parallel. slot < threads() is the calling worker's index, so per-thread
  // scratch can be picked without locks.
  template <typename Body>
  void forEachSpan(Extent extent, int alignment, const Body& body);

 private:
  template <typename Body>
  void forEachRow(Extent extent, const Body& body);
  template <typename Body>
  void forEachTile(Extent extent, int alignment, const Body& body);

  int threads_;
  int grain_;
  Partition partition_;
  oneapi::tbb::global_control limit_;
  oneapi::tbb::task_arena arena_;
};
static_assert(SpanScheduler<TbbScheduler>);

// Pixels per tile column: wide enough that a tile's packets amortise the
// per-task cost, a multiple of every packet width up to 64 lanes.
inline constexpr int kTileWidth = 64;

template <typename Body>
void TbbScheduler::forEachSpan(Extent extent, int alignment, const Body& body) {
  arena_.execute([&] {
    if (partition_ == Partition::tiles) {
      forEachTile(extent, alignment, body);
    } else {
      forEachRow(extent, body);
    }
  });
}

template <typename Body>
void TbbScheduler::forEachRow(Extent extent, const Body& body) {
  oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int>(0, extent.height, grain_),
                            [&](const oneapi::tbb::blocked_range<int>& rows) {
                              ZoneScopedN("rows");  // one zone per oneTBB chunk, never per ray
                              const int slot = oneapi::tbb::this_task_arena::current_thread_index();
                              for (int y = rows.begin(); y < rows.end(); ++y) body(slot, y, 0, extent.width);
                            });
}

template <typename Body>
void TbbScheduler::forEachTile(Extent extent, int alignment, const Body& body) {
  const int tileWidth = (std::max(kTileWidth, alignment) + alignment - 1) / alignment * alignment;
  const int columns = (extent.width + tileWidth - 1) / tileWidth;
  using Range = oneapi::tbb::blocked_range2d<int>;
  oneapi::tbb::parallel_for(Range(0, extent.height, grain_, 0, columns, 1), [&](const Range& tiles) {
    ZoneScopedN("tiles");
    const int slot = oneapi::tbb::this_task_arena::current_thread_index();
    for (int y = tiles.rows().begin(); y < tiles.rows().end(); ++y) {
      for (int c = tiles.cols().begin(); c < tiles.cols().end(); ++c) {
        body(slot, y, c * tileWidth, std::min(extent.width, (c + 1) * tileWidth));
      }
    }
  });
}

}  // namespace rt
