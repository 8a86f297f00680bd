#include "app/frame_recorder.h"

#include <gtest/gtest.h>

#include <charconv>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "app/run_identity.h"

namespace rt {
namespace {

std::vector<std::vector<std::string>> parseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        fields.emplace_back();
      else
        fields.back() += c;
    }
    rows.push_back(fields);
  }
  return rows;
}

RunIdentity identity() {
  return {"20261122T000000Z-abcdef",
          "random100",
          {RendererKind::sequential, 1, 1, "", std::nullopt, std::nullopt},
          optionsForStage(Stage::single_pass),
          {800, 600}};
}

std::size_t column(schema::FrameCsvColumn c) { return static_cast<std::size_t>(c); }

TEST(FrameCsv, HeaderIsTheSchemaColumns) {
  const auto rows = parseCsv(formatFrameCsv(identity(), {}));
  ASSERT_EQ(rows.size(), 1u);
  ASSERT_EQ(rows[0].size(), schema::kFrameCsvColumnNames.size());
  for (std::size_t i = 0; i < rows[0].size(); ++i) EXPECT_EQ(rows[0][i], schema::kFrameCsvColumnNames[i]);
}

TEST(FrameCsv, OneRowPerFrameWithFullPrecision) {
  const std::vector<FrameRecord> records{{.frame = 0,
                                          .warmup = true,
                                          .updateMs = 0.1,
                                          .renderMs = 123.456789012345,
                                          .presentMs = 1e-7,
                                          .gpuMs = {},
                                          .acquireMs = {}},
                                         {.frame = 1,
                                          .warmup = false,
                                          .updateMs = 0.2,
                                          .renderMs = 1.0 / 3.0,
                                          .presentMs = 2.5,
                                          .gpuMs = 0.0625,
                                          .acquireMs = {}}};
  const auto rows = parseCsv(formatFrameCsv(identity(), records));
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) EXPECT_EQ(row.size(), schema::kFrameCsvColumnNames.size());
  const auto& first = rows[1];
  EXPECT_EQ(first[column(schema::FrameCsvColumn::run_id)], "20261122T000000Z-abcdef");
  EXPECT_EQ(first[column(schema::FrameCsvColumn::renderer)], "sequential");
  EXPECT_EQ(first[column(schema::FrameCsvColumn::algorithm)], "single-pass");
  EXPECT_EQ(first[column(schema::FrameCsvColumn::early_exit)], "bounce");
  EXPECT_EQ(first[column(schema::FrameCsvColumn::warmup)], "1");
  EXPECT_EQ(first[column(schema::FrameCsvColumn::gpu_ms)], "");
  EXPECT_EQ(rows[2][column(schema::FrameCsvColumn::gpu_ms)], "0.0625");
  EXPECT_EQ(rows[2][column(schema::FrameCsvColumn::frame)], "1");

  // Every time reads back as exactly the double that was recorded.
  const std::string& text = rows[2][column(schema::FrameCsvColumn::render_ms)];
  double back = 0;
  std::from_chars(text.data(), text.data() + text.size(), back);
  EXPECT_EQ(back, 1.0 / 3.0);
}

TEST(FrameCsv, QuotesTextThatNeedsIt) {
  RunIdentity id = identity();
  id.scene = "odd, \"name\"";
  const auto rows = parseCsv(formatFrameCsv(id, std::vector<FrameRecord>{{}}));
  EXPECT_EQ(rows[1][column(schema::FrameCsvColumn::scene)], "odd, \"name\"");
}

// Known tallies, different in every field, so that a column read from the
// wrong field shows.
LaneCounters knownCounters(std::uint64_t scale) {
  LaneCounters c;
  c.raysPerDepth[0] = 384 * scale;
  c.raysPerDepth[1] = 120 * scale;
  c.raysPerDepth[2] = 7 * scale;
  c.nodeVisits = 11 * scale;
  c.nodeLaneSlots = 12 * scale;
  c.nodeLanesActive = 13 * scale;
  c.sphereTests = 14 * scale;
  c.sphereLaneSlots = 15 * scale;
  c.sphereLanesActive = 16 * scale;
  c.shadeLaneSlots = 17 * scale;
  c.shadeLanesActive = 18 * scale;
  return c;
}

std::string field(const std::vector<std::string>& row, schema::FrameCsvColumn c) { return row.at(column(c)); }

FrameRecord frameRecord(long long frame, bool warmup = false) {
  FrameRecord r;
  r.frame = frame;
  r.warmup = warmup;
  return r;
}

TEST(FrameCsv, CounterColumnsHoldTheFramesCountersOrNothing) {
  using enum schema::FrameCsvColumn;
  const std::vector<FrameRecord> records{frameRecord(0), frameRecord(1)};
  const std::vector<FrameCounters> counters{knownCounters(2), std::nullopt};
  const auto rows = parseCsv(formatFrameCsv(identity(), records, counters));
  ASSERT_EQ(rows.size(), 3u);
  const auto& counted = rows[1];
  EXPECT_EQ(field(counted, rays), "1022");
  EXPECT_EQ(field(counted, rays_per_depth), "768/240/14") << "up to the deepest depth that traced a ray";
  EXPECT_EQ(field(counted, node_visits), "22");
  EXPECT_EQ(field(counted, node_lane_slots), "24");
  EXPECT_EQ(field(counted, node_lanes_active), "26");
  EXPECT_EQ(field(counted, sphere_tests), "28");
  EXPECT_EQ(field(counted, sphere_lane_slots), "30");
  EXPECT_EQ(field(counted, sphere_lanes_active), "32");
  EXPECT_EQ(field(counted, shade_lane_slots), "34");
  EXPECT_EQ(field(counted, shade_lanes_active), "36");
  for (const auto c : {rays, rays_per_depth, node_visits, node_lane_slots, node_lanes_active, sphere_tests,
                       sphere_lane_slots, sphere_lanes_active, shade_lane_slots, shade_lanes_active}) {
    EXPECT_EQ(field(rows[2], c), "") << schema::kFrameCsvColumnNames[column(c)] << ": a frame without counters";
  }
  // No counters at all (a run without --counters): the columns are there, empty.
  const auto uncounted = parseCsv(formatFrameCsv(identity(), records));
  EXPECT_EQ(field(uncounted[1], rays), "");
  EXPECT_EQ(uncounted[1].size(), schema::kFrameCsvColumnNames.size());
  EXPECT_THROW(formatFrameCsv(identity(), records, std::vector<FrameCounters>{std::nullopt}), std::logic_error);
}

TEST(FrameCsv, RaysPerDepthSkipsNoDepthInside) {
  LaneCounters c;
  c.raysPerDepth[0] = 5;
  c.raysPerDepth[3] = 1;  // depths 1 and 2 traced nothing, depth 3 did
  const std::vector<FrameCounters> counters{c};
  const auto rows = parseCsv(formatFrameCsv(identity(), std::vector<FrameRecord>{{}}, counters));
  EXPECT_EQ(field(rows[1], schema::FrameCsvColumn::rays_per_depth), "5/0/0/1");
  EXPECT_EQ(field(rows[1], schema::FrameCsvColumn::rays), "6");
}

TEST(FrameCsv, TraversalColumnsAreTheRenderersOrEmpty) {
  using enum schema::FrameCsvColumn;
  RunIdentity id = identity();
  const std::vector<FrameRecord> one{{}};
  auto row = parseCsv(formatFrameCsv(id, one))[1];
  EXPECT_EQ(field(row, traversal), "") << "none applies to the sequential renderer";
  EXPECT_EQ(field(row, hybrid_threshold), "");
  id.renderer.traversal = Traversal::single;
  row = parseCsv(formatFrameCsv(id, one))[1];
  EXPECT_EQ(field(row, traversal), "single");
  EXPECT_EQ(field(row, hybrid_threshold), "");
  id.renderer.traversal = Traversal::hybrid;
  id.renderer.hybridThreshold = 9;
  row = parseCsv(formatFrameCsv(id, one))[1];
  EXPECT_EQ(field(row, traversal), "hybrid");
  EXPECT_EQ(field(row, hybrid_threshold), "9");
}

// The GPU renderer's axes as its RendererInfo reports them (gpu_schedule
// and gpu_path of one value each since the others were retired); gpu_bvh
// is empty with accel none, and all three for the CPU renderers.
TEST(FrameCsv, GpuAxisColumnsAreTheRenderersOrEmpty) {
  using enum schema::FrameCsvColumn;
  RunIdentity id = identity();
  const std::vector<FrameRecord> one{{}};
  auto row = parseCsv(formatFrameCsv(id, one))[1];
  for (const auto c : {gpu_bvh, gpu_schedule, gpu_path}) {
    EXPECT_EQ(field(row, c), "") << schema::kFrameCsvColumnNames[column(c)] << ": none applies to a CPU renderer";
  }
  id.renderer.kind = RendererKind::gpu;
  id.renderer.gpuSchedule = GpuSchedule::pixel;
  id.renderer.gpuPath = GpuPath::megakernel;
  row = parseCsv(formatFrameCsv(id, one))[1];
  EXPECT_EQ(field(row, gpu_bvh), "") << "accel none: no BVH";
  EXPECT_EQ(field(row, gpu_schedule), "pixel");
  EXPECT_EQ(field(row, gpu_path), "megakernel");
  id.renderer.gpuBvh = GpuBvh::wide;
  row = parseCsv(formatFrameCsv(id, one))[1];
  EXPECT_EQ(field(row, gpu_bvh), "wide");
  EXPECT_EQ(field(row, gpu_schedule), "pixel");
  EXPECT_EQ(field(row, gpu_path), "megakernel");
  EXPECT_EQ(field(row, traversal), "") << "the SIMD kernel's column stays empty";
  EXPECT_EQ(row.size(), schema::kFrameCsvColumnNames.size());
}

// The counter columns do not depend on the renderer: a GPU run's counters
// fill them as a SIMD run's do.
TEST(FrameCsv, CounterColumnsOfAGpuRun) {
  using enum schema::FrameCsvColumn;
  RunIdentity id = identity();
  id.renderer = {RendererKind::gpu, 0, 0, "", std::nullopt, std::nullopt};
  id.renderer.gpuSchedule = GpuSchedule::pixel;
  id.renderer.gpuPath = GpuPath::megakernel;
  id.options.counters = true;
  const std::vector<FrameRecord> records{frameRecord(0)};
  const std::vector<FrameCounters> counters{knownCounters(1)};
  const auto rows = parseCsv(formatFrameCsv(id, records, counters));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(field(rows[1], renderer), "gpu");
  EXPECT_EQ(field(rows[1], rays), "511");
  EXPECT_EQ(field(rows[1], rays_per_depth), "384/120/7");
  EXPECT_EQ(field(rows[1], node_visits), "11");
  EXPECT_EQ(field(rows[1], shade_lanes_active), "18");
}

TEST(FrameCounterTotals, SumTheMeasuredFramesFieldByField) {
  const std::vector<FrameRecord> records{frameRecord(0, true), frameRecord(1), frameRecord(2), frameRecord(3)};
  const std::vector<FrameCounters> counters{knownCounters(1000), knownCounters(1), std::nullopt, knownCounters(3)};
  const auto total = measuredCounterTotals(records, counters);
  ASSERT_TRUE(total);
  EXPECT_EQ(total->raysPerDepth[0], 384u * 4) << "the warm-up frame is left out";
  EXPECT_EQ(total->raysPerDepth[2], 7u * 4);
  EXPECT_EQ(total->nodeVisits, 11u * 4);
  EXPECT_EQ(total->shadeLanesActive, 18u * 4);
  EXPECT_EQ(total->deepestDepth(), 3);
  EXPECT_FALSE(measuredCounterTotals(records, {})) << "no counters: no totals";
  const std::vector<FrameCounters> onlyWarmup{knownCounters(1), std::nullopt, std::nullopt, std::nullopt};
  EXPECT_FALSE(measuredCounterTotals(records, onlyWarmup)) << "no measured frame counted";
}

TEST(FrameRecorder, KeepsCountersOnlyWhenCounting) {
  FrameRecorder counting(2, true);
  counting.record(frameRecord(0), knownCounters(1));
  counting.record(frameRecord(1), std::nullopt);
  counting.record(frameRecord(2), knownCounters(5));  // past the capacity
  ASSERT_EQ(counting.counters().size(), 2u);
  EXPECT_EQ(counting.counters()[0]->nodeVisits, 11u);
  EXPECT_FALSE(counting.counters()[1]);
  FrameRecorder plain(2);
  plain.record(frameRecord(0), knownCounters(1));
  EXPECT_EQ(plain.records().size(), 1u);
  EXPECT_TRUE(plain.counters().empty());
  const auto [records, counters] = std::move(counting).take();
  EXPECT_EQ(records.size(), 2u);
  EXPECT_EQ(counters.size(), 2u);
}

TEST(FrameRecorder, NeverGrowsPastItsCapacity) {
  FrameRecorder recorder(2);
  for (int i = 0; i < 5; ++i) {
    FrameRecord r;
    r.frame = i;
    recorder.record(r);
  }
  ASSERT_EQ(recorder.records().size(), 2u);
  EXPECT_EQ(recorder.records()[1].frame, 1);
}

TEST(EarlyExitNames, JoinInSchemaOrder) {
  EXPECT_EQ(EarlyExitSet().toString(), "none");
  EXPECT_EQ(EarlyExitSet::all().toString(), "bounce+sphere+discriminant");
  EarlyExitSet s;
  s.add(EarlyExit::discriminant);
  s.add(EarlyExit::bounce);
  EXPECT_EQ(s.toString(), "bounce+discriminant");
}

}  // namespace
}  // namespace rt
