#include "app/run_metadata.h"

#include <gtest/gtest.h>

#include "core/sha256.h"
#include "render/cpu_renderers.h"
#include "test_support.h"

namespace rt {
namespace {

TEST(RunMetadata, HasEverySchemaKeyAndTheSceneHash) {
  RunConfig config;
  config.scenePath = test::scenePath("default");
  config.commandLine = {"raytracer", "--sequential"};
  const Scene scene = loadScene(config.scenePath);
  const auto now = std::chrono::system_clock::now();
  const RunIdentity id{makeRunId(now), scene.name, SequentialRenderer().info(), config.options, config.extent};
  const nlohmann::json meta = makeRunMetadata(config, id, scene, {now, now});
  for (auto key : schema::kRunMetadataKeyNames) EXPECT_TRUE(meta.contains(std::string(key))) << key;
  EXPECT_EQ(meta.size(), schema::kRunMetadataKeyNames.size());
  EXPECT_EQ(meta["scene"]["sha256"], sha256HexOfFile(config.scenePath));
  EXPECT_EQ(meta["run_id"], id.runId);
  EXPECT_EQ(meta["config"]["renderer"], "sequential");
  EXPECT_GE(meta["host"]["logical_cores"].get<int>(), 1);
  const auto commit = meta["build"]["git_commit"].get<std::string>();
  EXPECT_TRUE(commit.size() == 40 || commit == "unknown") << commit;
}

TEST(RunMetadata, WindowObjectIsTheRunsWindowOutcome) {
  RunConfig config;
  config.scenePath = test::scenePath("default");
  const Scene scene = loadScene(config.scenePath);
  const auto now = std::chrono::system_clock::now();
  const RunIdentity id{makeRunId(now), scene.name, SequentialRenderer().info(), config.options, config.extent};
  EXPECT_TRUE(makeRunMetadata(config, id, scene, {now, now})["window"].is_null());
  const WindowOutcome window{.swapchain = {.surfaceFormat = "B8G8R8A8_SRGB", .imageCount = 3, .framesPresented = 7},
                             .closed = true};
  const nlohmann::json written = makeRunMetadata(config, id, scene, {now, now}, window)["window"];
  EXPECT_EQ(written["surface_format"], "B8G8R8A8_SRGB");
  EXPECT_EQ(written["swapchain_images"], 3);
  EXPECT_EQ(written["frames_presented"], 7);
  EXPECT_EQ(written["closed"], true);
}

TEST(RunMetadata, TimesAreRfc3339Utc) {
  const auto t = std::chrono::system_clock::time_point(std::chrono::milliseconds(1'700'000'000'123));
  EXPECT_EQ(formatRfc3339(t), "2023-11-14T22:13:20.123Z");
  EXPECT_EQ(makeRunId(t).rfind("20231114T221320Z-", 0), 0u);
}

}  // namespace
}  // namespace rt
