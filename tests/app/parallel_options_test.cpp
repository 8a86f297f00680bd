// --threads, --lanes, --grain, --partition: parsing, the renderers they
// apply to, and the CSV columns they fill.
#include <gtest/gtest.h>

#include <initializer_list>
#include <sstream>
#include <vector>

#include "app/cli.h"
#include "app/cli_test_support.h"
#include "app/frame_recorder.h"
#include "app/run_identity.h"

namespace rt {
namespace {

using test::parse;
using test::parseFails;
using test::parseOk;

TEST(ParallelOptions, DefaultsAreAllCoresNativeLanesRows) {
  const RunConfig c = parseOk({"--simd"});
  EXPECT_EQ(c.parallel.threads, ParallelSettings::kAllCores);
  EXPECT_EQ(c.parallel.lanes, ParallelSettings::kNativeLanes);
  EXPECT_EQ(c.parallel.grain, 1);
  EXPECT_EQ(c.parallel.partition, Partition::rows);
}

TEST(ParallelOptions, ParsedForTheRenderersTheyApplyTo) {
  const RunConfig simd = parseOk({"--simd", "--threads", "2", "--lanes", "4", "--grain", "8", "--partition", "tiles"});
  EXPECT_EQ(simd.renderer, RendererKind::simd_tbb);
  EXPECT_EQ(simd.parallel.threads, 2);
  EXPECT_EQ(simd.parallel.lanes, 4);
  EXPECT_EQ(simd.parallel.grain, 8);
  EXPECT_EQ(simd.parallel.partition, Partition::tiles);
  EXPECT_EQ(parseOk({"--simd-only", "--lanes", "native"}).parallel.lanes, ParallelSettings::kNativeLanes);
  EXPECT_EQ(parseOk({"--simd-only", "--lanes", "16"}).parallel.lanes, 16);
  EXPECT_EQ(parseOk({"--tbb-only", "--threads", "3"}).parallel.threads, 3);
  EXPECT_EQ(parseOk({"--sequential", "--threads", "1"}).parallel.threads, 1);  // what it does anyway
}

TEST(ParallelOptions, BadValuesExitTwoWithUsage) {
  for (const auto& args : std::vector<std::vector<const char*>>{{"--simd", "--threads", "0"},
                                                                {"--simd", "--threads", "many"},
                                                                {"--simd", "--lanes", "3"},
                                                                {"--simd", "--lanes", "32"},
                                                                {"--simd", "--grain", "0"},
                                                                {"--simd", "--partition", "columns"}}) {
    std::vector<const char*> argv{"raytracer"};
    argv.insert(argv.end(), args.begin(), args.end());
    auto result = parseCommandLine(static_cast<int>(argv.size()), argv.data());
    const auto* exit = std::get_if<CliExit>(&result);
    ASSERT_NE(exit, nullptr) << args[1] << " " << args[2];
    EXPECT_EQ(exit->code, kExitBadInput);
    EXPECT_NE(exit->error.find("Usage"), std::string::npos) << exit->error;
  }
}

TEST(ParallelOptions, RejectedWhereTheRendererIgnoresThem) {
  EXPECT_NE(parseFails({"--sequential", "--threads", "2"}).error.find("--threads applies to"), std::string::npos);
  EXPECT_NE(parseFails({"--simd-only", "--threads", "2"}).error.find("--threads applies to"), std::string::npos);
  EXPECT_NE(parseFails({"--tbb-only", "--lanes", "4"}).error.find("--lanes applies to"), std::string::npos);
  EXPECT_NE(parseFails({"--simd-only", "--grain", "4"}).error.find("--grain applies to"), std::string::npos);
  EXPECT_NE(parseFails({"--sequential", "--partition", "tiles"}).error.find("--partition applies to"),
            std::string::npos);
  EXPECT_EQ(parseFails({"--gpu", "--lanes", "4"}).code, kExitBadInput);
}

std::vector<std::string> csvRow(const std::string& text, std::size_t line) {
  std::stringstream lines(text);
  std::string row;
  for (std::size_t i = 0; i <= line; ++i) std::getline(lines, row);
  std::vector<std::string> fields(1);
  for (const char c : row) {
    if (c == ',')
      fields.emplace_back();
    else
      fields.back() += c;
  }
  return fields;
}

std::string field(const std::vector<std::string>& row, schema::FrameCsvColumn c) {
  return row.at(static_cast<std::size_t>(c));
}

TEST(ParallelOptions, GrainAndPartitionColumnsDescribeOneTbbRuns) {
  const std::vector<FrameRecord> one{FrameRecord{}};
  const auto identity = [](RendererInfo renderer) {
    return RunIdentity{"run", "random100", std::move(renderer), optionsForStage(Stage::optimized), {800, 600}};
  };
  auto row = csvRow(formatFrameCsv(identity({RendererKind::simd_tbb, 2, 16, "AVX3", 4, Partition::tiles}), one), 1);
  EXPECT_EQ(field(row, schema::FrameCsvColumn::threads), "2");
  EXPECT_EQ(field(row, schema::FrameCsvColumn::lanes), "16");
  EXPECT_EQ(field(row, schema::FrameCsvColumn::simd_target), "AVX3");
  EXPECT_EQ(field(row, schema::FrameCsvColumn::grain), "4");
  EXPECT_EQ(field(row, schema::FrameCsvColumn::partition), "tiles");

  row = csvRow(formatFrameCsv(identity({RendererKind::simd_only, 1, 4, "AVX2", std::nullopt, std::nullopt}), one), 1);
  EXPECT_EQ(field(row, schema::FrameCsvColumn::grain), "0");
  EXPECT_EQ(field(row, schema::FrameCsvColumn::partition), "");
}

}  // namespace
}  // namespace rt
