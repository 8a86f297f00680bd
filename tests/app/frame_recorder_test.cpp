#include "app/frame_recorder.h"

#include <gtest/gtest.h>

#include <charconv>
#include <sstream>
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
