#include "app/run_summary.h"

#include <gtest/gtest.h>

#include <vector>

namespace rt {
namespace {

FrameRecord frame(long long k, bool warmup, double renderMs, std::optional<double> gpuMs = std::nullopt) {
  return {.frame = k,
          .warmup = warmup,
          .updateMs = 0.01,
          .renderMs = renderMs,
          .presentMs = 1.0,
          .gpuMs = gpuMs,
          .acquireMs = {}};
}

TEST(RunSummary, MeasuredFramesOnlyWithTheMedianOfAnEvenCount) {
  const std::vector<FrameRecord> records{frame(0, true, 100.0), frame(1, false, 4.0), frame(2, false, 1.0),
                                         frame(3, false, 3.0), frame(4, false, 2.0)};
  const RunSummary s = summarizeRun({1000, 1000}, records);
  EXPECT_EQ(s.measuredFrames, 4u);
  EXPECT_DOUBLE_EQ(s.renderMs.median, 2.5);
  EXPECT_DOUBLE_EQ(s.renderMs.min, 1.0);
  EXPECT_DOUBLE_EQ(s.renderMs.max, 4.0);  // the warm-up's 100 ms is not counted
  EXPECT_FALSE(s.gpuMs);
  EXPECT_DOUBLE_EQ(s.primaryRaysPerSecond, 1e6 / 2.5e-3);
}

TEST(RunSummary, GpuTimeWhereMeasuredAndPrinted) {
  const std::vector<FrameRecord> records{frame(0, false, 2.0, 1.5), frame(1, false, 3.0, 0.5),
                                         frame(2, false, 1.0, 1.0)};
  const RunSummary s = summarizeRun({10, 10}, records);
  ASSERT_TRUE(s.gpuMs);
  EXPECT_DOUBLE_EQ(s.gpuMs->median, 1.0);
  RunIdentity id;
  id.scene = "default";
  id.extent = {10, 10};
  const std::string text = formatRunSummary(id, s);
  EXPECT_NE(text.find("render_ms  median 2.000"), std::string::npos) << text;
  EXPECT_NE(text.find("gpu_ms     median 1.000"), std::string::npos) << text;
}

TEST(RunSummary, NoMeasuredFramesGivesZeros) {
  const RunSummary s = summarizeRun({10, 10}, {});
  EXPECT_EQ(s.measuredFrames, 0u);
  EXPECT_EQ(s.primaryRaysPerSecond, 0.0);
}

}  // namespace
}  // namespace rt
