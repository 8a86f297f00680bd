// The schedulers hand out every pixel of the image exactly once, in spans
// whose first pixel is a multiple of the kernel's alignment, from worker
// slots below threads().
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <vector>

#include "render/schedule/serial_scheduler.h"
#include "render/schedule/tbb_scheduler.h"

namespace rt {
namespace {

template <class Scheduler>
void expectEveryPixelOnce(Scheduler& scheduler, const std::string& label) {
  const Extent extent{203, 19};
  for (const int alignment : {1, 4, 16}) {
    std::vector<std::atomic<int>> visits(extent.pixelCount());
    std::atomic<bool> misaligned = false, badSlot = false;
    scheduler.forEachSpan(extent, alignment, [&](int slot, int y, int x0, int x1) {
      if (x0 % alignment != 0) misaligned = true;
      if (slot < 0 || slot >= scheduler.threads()) badSlot = true;
      for (int x = x0; x < x1; ++x) ++visits[static_cast<std::size_t>(y) * extent.width + x];
    });
    EXPECT_FALSE(misaligned) << label << " alignment " << alignment;
    EXPECT_FALSE(badSlot) << label;
    EXPECT_TRUE(std::ranges::all_of(visits, [](const std::atomic<int>& v) { return v == 1; }))
        << label << " alignment " << alignment;
  }
}

TEST(TbbScheduler, HandsOutEveryPixelOnceWithAlignedSpans) {
  for (const Partition partition : {Partition::rows, Partition::tiles}) {
    TbbScheduler scheduler(3, 2, partition);
    expectEveryPixelOnce(scheduler, std::string(nameOf(partition)));
  }
}

TEST(TbbScheduler, RejectsBadSettings) {
  EXPECT_THROW(TbbScheduler(-1, 1, Partition::rows), std::invalid_argument);
  EXPECT_THROW(TbbScheduler(2, 0, Partition::rows), std::invalid_argument);
}

TEST(SerialScheduler, HandsOutEveryPixelOnceFromOneSlot) {
  SerialScheduler scheduler;
  EXPECT_EQ(scheduler.threads(), 1);
  EXPECT_FALSE(scheduler.grain());
  expectEveryPixelOnce(scheduler, "serial");
}

}  // namespace
}  // namespace rt
