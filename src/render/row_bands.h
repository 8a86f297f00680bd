#pragma once
// The single-threaded renderers walk the image in bands of rows, each band
// one Tracy zone named like the oneTBB chunks' ("rows"), so the profiler
// shows every renderer's work split the same way without a zone per row.
#include <algorithm>

#include "core/profiler.h"

namespace rt {

inline constexpr int kRowsPerBand = 16;

template <typename Body>
void forEachRowBand(int height, const Body& body) {
  for (int first = 0; first < height; first += kRowsPerBand) {
    ZoneScopedN("rows");
    const int last = std::min(height, first + kRowsPerBand);
    for (int y = first; y < last; ++y) body(y);
  }
}

}  // namespace rt
