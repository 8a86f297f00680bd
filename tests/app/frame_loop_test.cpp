#include "app/frame_loop.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "app/run_metadata.h"
#include "core/sha256.h"
#include "render/render_test_support.h"
#include "render/sequential_renderer.h"
#include "test_support.h"

namespace rt {
namespace {

RunConfig smallRun() {
  RunConfig c;
  c.scenePath = test::scenePath("default");
  c.extent = {32, 24};
  c.warmupFrames = 2;
  c.measuredFrames = 3;
  return c;
}

TEST(FrameLoop, RecordsEveryFrameWithWarmupFlags) {
  const Scene scene = loadScene(smallRun().scenePath);
  SequentialRenderer renderer;
  const FrameLoopResult r = runFrameLoop(renderer, scene, smallRun());
  EXPECT_FALSE(r.failure);
  ASSERT_EQ(r.records.size(), 5u);
  for (std::size_t k = 0; k < r.records.size(); ++k) {
    EXPECT_EQ(r.records[k].frame, static_cast<long long>(k));
    EXPECT_EQ(r.records[k].warmup, k < 2);
    EXPECT_GT(r.records[k].renderMs, 0.0);
    EXPECT_GE(r.records[k].updateMs, 0.0);
    EXPECT_GE(r.records[k].presentMs, 0.0);
    EXPECT_FALSE(r.records[k].gpuMs);
  }
}

TEST(FrameLoop, SavedFrameIsThatAnimationFrame) {
  RunConfig config = smallRun();
  config.saveFrames = {{3, "unused.png"}, {0, "unused0.png"}};
  const Scene scene = loadScene(config.scenePath);
  SequentialRenderer renderer;
  const FrameLoopResult r = runFrameLoop(renderer, scene, config);
  ASSERT_EQ(r.savedFrames.size(), 2u);
  SequentialRenderer fresh;
  for (std::size_t i = 0; i < 2; ++i) {
    const Image direct = test::renderFrame(fresh, scene, config.extent, config.options, config.saveFrames[i].frame);
    EXPECT_TRUE(std::ranges::equal(direct.pixels(), r.savedFrames[i].pixels())) << "frame " << config.saveFrames[i].frame;
  }
}

// A renderer whose device fails at a given frame, to exercise the loop's error path.
class FailingRenderer final : public Renderer {
 public:
  explicit FailingRenderer(long long failAt) : failAt_(failAt) {}
  RendererInfo info() const override { return {}; }
  void prepare(const Scene&, Extent, const RenderOptions&) override {}
  void render(const CameraFrame&) override {
    if (frame_++ == failAt_) throw std::runtime_error("device lost");
  }
  void present(Image&) override {}

 private:
  long long failAt_;
  long long frame_ = 0;
};

TEST(FrameLoop, KeepsCompletedFramesWhenAFrameFails) {
  const Scene scene = loadScene(smallRun().scenePath);
  FailingRenderer renderer(3);
  const FrameLoopResult r = runFrameLoop(renderer, scene, smallRun());
  ASSERT_TRUE(r.failure);
  EXPECT_EQ(r.records.size(), 3u);
  EXPECT_THROW(std::rethrow_exception(r.failure), std::runtime_error);
}

TEST(RunMetadata, HasEverySchemaKeyAndTheSceneHash) {
  RunConfig config = smallRun();
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
  EXPECT_EQ(meta["build"]["git_commit"].get<std::string>().size() == 40 ||
                meta["build"]["git_commit"] == "unknown",
            true);
}

TEST(RunMetadata, TimesAreRfc3339Utc) {
  const auto t = std::chrono::system_clock::time_point(std::chrono::milliseconds(1'700'000'000'123));
  EXPECT_EQ(formatRfc3339(t), "2023-11-14T22:13:20.123Z");
  EXPECT_EQ(makeRunId(t).rfind("20231114T221320Z-", 0), 0u);
}

}  // namespace
}  // namespace rt
