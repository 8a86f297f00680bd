#include "app/frame_loop.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/run_identity.h"
#include "app/run_metadata.h"
#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
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

// The loop runs on a prepared renderer (main prepares it before building
// the run's identity); the tests prepare it the same way.
FrameLoopResult prepareAndRun(Renderer& renderer, const Scene& scene, const RunConfig& config,
                              LiveView* view = nullptr) {
  renderer.prepare(scene, config.extent, config.options);
  return runFrameLoop(renderer, scene, config, view);
}

TEST(FrameLoop, RecordsEveryFrameWithWarmupFlags) {
  const Scene scene = loadScene(smallRun().scenePath);
  SequentialRenderer renderer;
  const FrameLoopResult r = prepareAndRun(renderer, scene, smallRun());
  EXPECT_FALSE(r.failure);
  ASSERT_EQ(r.records.size(), 5u);
  for (std::size_t k = 0; k < r.records.size(); ++k) {
    EXPECT_EQ(r.records[k].frame, static_cast<long long>(k));
    EXPECT_EQ(r.records[k].warmup, k < 2);
    EXPECT_GT(r.records[k].renderMs, 0.0);
    EXPECT_FALSE(r.records[k].gpuMs);
  }
}

using Milliseconds = std::chrono::duration<double, std::milli>;

// Render and Present that take at least known times (sleeps), different
// from each other, so that a phase timed over the wrong interval shows.
class SleepingRenderer final : public Renderer {
 public:
  static constexpr std::chrono::milliseconds kRenderSleep{4};
  static constexpr std::chrono::milliseconds kPresentSleep{2};
  RendererInfo info() const override { return {}; }
  void prepare(const Scene&, Extent, const RenderOptions&) override {}
  void render(const CameraFrame&) override { std::this_thread::sleep_for(kRenderSleep); }
  void present() override { std::this_thread::sleep_for(kPresentSleep); }
  void readPresented(Image&) override {}
};

// Each phase's time covers its own work (at least the sleep in it), and the
// phases of all frames, which follow one another, fit in the loop's wall
// time: a phase timed over a neighbour's interval too would exceed it.
TEST(FrameLoop, PhaseTimesCoverTheirOwnWorkAndSumWithinTheLoop) {
  const Scene scene = loadScene(smallRun().scenePath);
  SleepingRenderer renderer;
  const auto start = std::chrono::steady_clock::now();
  const FrameLoopResult r = prepareAndRun(renderer, scene, smallRun());
  const double loopMs = Milliseconds(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.records.size(), 5u);
  const double renderSleepMs = Milliseconds(SleepingRenderer::kRenderSleep).count();
  const double presentSleepMs = Milliseconds(SleepingRenderer::kPresentSleep).count();
  double phasesMs = 0.0;
  for (const FrameRecord& f : r.records) {
    EXPECT_GE(f.renderMs, renderSleepMs) << "frame " << f.frame;
    EXPECT_GE(f.presentMs, presentSleepMs) << "frame " << f.frame;
    phasesMs += f.updateMs + f.renderMs + f.presentMs;
  }
  EXPECT_LE(phasesMs, loopMs);
}

// A renderer that reports known counters: frame k's (counted by render()
// calls) trace 100 + k primary rays, so a frame recorded with another
// frame's counters shows. It says what the SIMD kernel would: its traversal.
class CountingRenderer final : public Renderer {
 public:
  RendererInfo info() const override {
    RendererInfo info;
    info.kind = RendererKind::simd_only;
    info.traversal = Traversal::hybrid;
    info.hybridThreshold = 5;
    return info;
  }
  void prepare(const Scene&, Extent, const RenderOptions& options) override { counting_ = options.counters; }
  void render(const CameraFrame&) override { ++rendered_; }
  void present() override {}
  void readPresented(Image&) override {}
  [[nodiscard]] std::optional<LaneCounters> lastCounters() const override {
    ++asked_;
    if (!counting_) return std::nullopt;
    LaneCounters c;
    c.raysPerDepth[0] = 100 + static_cast<std::uint64_t>(rendered_ - 1);
    c.raysPerDepth[1] = 3;
    c.sphereLaneSlots = 8;
    c.sphereLanesActive = 2;
    return c;
  }
  [[nodiscard]] int asked() const { return asked_; }

 private:
  bool counting_ = false;
  long long rendered_ = 0;
  mutable int asked_ = 0;
};

RunConfig countingRun() {
  RunConfig config = smallRun();
  config.options.counters = true;
  return config;
}

TEST(FrameLoop, RecordsEachFramesCountersWithCounters) {
  const RunConfig config = countingRun();
  const Scene scene = loadScene(config.scenePath);
  CountingRenderer renderer;
  const FrameLoopResult r = prepareAndRun(renderer, scene, config);
  ASSERT_EQ(r.records.size(), 5u);
  ASSERT_EQ(r.counters.size(), 5u) << "one per record";
  for (std::size_t k = 0; k < r.counters.size(); ++k) {
    ASSERT_TRUE(r.counters[k]) << "frame " << k;
    EXPECT_EQ(r.counters[k]->raysPerDepth[0], 100 + k) << "frame " << k << " recorded another frame's counters";
    EXPECT_EQ(r.counters[k]->sphereLanesActive, 2u);
  }
  EXPECT_EQ(renderer.asked(), 5);
}

TEST(FrameLoop, RecordsNoCountersWithoutCounters) {
  const Scene scene = loadScene(smallRun().scenePath);
  CountingRenderer renderer;
  const FrameLoopResult r = prepareAndRun(renderer, scene, smallRun());
  EXPECT_EQ(r.records.size(), 5u);
  EXPECT_TRUE(r.counters.empty());
  EXPECT_EQ(renderer.asked(), 0) << "the loop does not ask a renderer that was not asked to count";
}

// The counting run's outputs: the CSV rows carry each frame's counters and
// the renderer's traversal, the metadata the measured frames' totals.
TEST(FrameLoop, CountersAndTraversalReachTheCsvAndTheMetadata) {
  const RunConfig config = countingRun();
  const Scene scene = loadScene(config.scenePath);
  CountingRenderer renderer;
  const FrameLoopResult r = prepareAndRun(renderer, scene, config);
  const RunIdentity id = makeRunIdentity("run", scene, renderer, config, {});

  const std::string csv = formatFrameCsv(id, r.records, r.counters);
  std::vector<std::string> lines;
  std::stringstream text(csv);
  for (std::string line; std::getline(text, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_NE(lines[0].find("traversal,hybrid_threshold"), std::string::npos) << lines[0];
  // rays_per_depth, node_visits ... shade_lanes_active end each row.
  EXPECT_TRUE(lines[1].ends_with(",103,100/3,0,0,0,0,8,2,0,0")) << lines[1];
  EXPECT_TRUE(lines[5].ends_with(",107,104/3,0,0,0,0,8,2,0,0")) << lines[5];
  EXPECT_NE(lines[1].find(",hybrid,5,"), std::string::npos) << lines[1];

  const auto now = std::chrono::system_clock::now();
  const nlohmann::json meta =
      makeRunMetadata(config, id, scene, {now, now}, std::nullopt, measuredCounterTotals(r.records, r.counters));
  const nlohmann::json& totals = meta["lane_counters"];
  EXPECT_EQ(totals["rays"], 102 + 103 + 104 + 3 * 3) << "frames 2..4, the measured ones";
  EXPECT_EQ(totals["rays_per_depth"], nlohmann::json::array({102 + 103 + 104, 9}));
  EXPECT_EQ(totals["sphere_lane_slots"], 24);
  EXPECT_EQ(meta["config"]["traversal"], "hybrid");
  EXPECT_EQ(meta["config"]["hybrid_threshold"], 5);
  EXPECT_EQ(meta["config"]["counters"], true);
}

// The loop's side of a window: open for `openFrames` frames, then closed;
// reports a fixed acquire wait. What the window itself does is tested
// end to end under Xvfb (tests/window).
class ClosingView final : public LiveView {
 public:
  explicit ClosingView(int openFrames) : openFrames_(openFrames) {}
  bool keepRunning() override { return asked_++ < openFrames_; }
  [[nodiscard]] std::optional<double> lastAcquireMs() const override { return 0.25; }
  void frameDone(const FrameRecord& record) override { shown_.push_back(record.frame); }
  [[nodiscard]] const std::vector<long long>& shown() const { return shown_; }

 private:
  int openFrames_;
  int asked_ = 0;
  std::vector<long long> shown_;
};

TEST(FrameLoop, RunsUntilTheViewClosesWithFramesZero) {
  RunConfig config = smallRun();
  config.present = PresentMode::window;
  config.measuredFrames = 0;  // until closed
  const Scene scene = loadScene(config.scenePath);
  SequentialRenderer renderer;
  ClosingView view(7);
  const FrameLoopResult r = prepareAndRun(renderer, scene, config, &view);
  EXPECT_FALSE(r.failure);
  ASSERT_EQ(r.records.size(), 7u) << "every frame before the close is recorded, past warmup + 0";
  EXPECT_EQ(view.shown(), (std::vector<long long>{0, 1, 2, 3, 4, 5, 6}));
  for (const FrameRecord& record : r.records) EXPECT_EQ(record.acquireMs, 0.25);
}

TEST(FrameLoop, ClosingTheViewEndsAFixedRunEarly) {
  const Scene scene = loadScene(smallRun().scenePath);
  SequentialRenderer renderer;
  ClosingView view(2);
  const FrameLoopResult r = prepareAndRun(renderer, scene, smallRun(), &view);
  EXPECT_EQ(r.records.size(), 2u);
  ClosingView stays(100);
  EXPECT_EQ(prepareAndRun(renderer, scene, smallRun(), &stays).records.size(), 5u) << "no more than asked for";
}

TEST(FrameLoop, SavedFrameIsThatAnimationFrame) {
  RunConfig config = smallRun();
  config.saveFrames = {{3, "unused.png"}, {0, "unused0.png"}};
  const Scene scene = loadScene(config.scenePath);
  SequentialRenderer renderer;
  const FrameLoopResult r = prepareAndRun(renderer, scene, config);
  ASSERT_EQ(r.savedFrames.size(), 2u);
  SequentialRenderer fresh;
  for (std::size_t i = 0; i < 2; ++i) {
    const long long frame = config.saveFrames[i].frame;
    EXPECT_TRUE(r.savedFrames[i].filled) << "frame " << frame;
    const Image direct = test::renderFrame(fresh, scene, config.extent, config.options, frame);
    EXPECT_TRUE(std::ranges::equal(direct.pixels(), r.savedFrames[i].image.pixels())) << "frame " << frame;
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
  void present() override {}
  void readPresented(Image&) override {}

 private:
  long long failAt_;
  long long frame_ = 0;
};

TEST(FrameLoop, KeepsCompletedFramesWhenAFrameFails) {
  const Scene scene = loadScene(smallRun().scenePath);
  FailingRenderer renderer(3);
  const FrameLoopResult r = prepareAndRun(renderer, scene, smallRun());
  ASSERT_TRUE(r.failure);
  EXPECT_EQ(r.records.size(), 3u);
  EXPECT_THROW(std::rethrow_exception(r.failure), std::runtime_error);
}

TEST(FrameLoop, SavedFramesTheRunDidNotReachStayUnfilled) {
  RunConfig config = smallRun();
  config.saveFrames = {{1, "before.png"}, {4, "after.png"}};
  const Scene scene = loadScene(config.scenePath);
  FailingRenderer renderer(3);
  const FrameLoopResult r = prepareAndRun(renderer, scene, config);
  ASSERT_TRUE(r.failure);
  ASSERT_EQ(r.savedFrames.size(), 2u);
  EXPECT_TRUE(r.savedFrames[0].filled) << "frame 1 completed before the failure";
  EXPECT_FALSE(r.savedFrames[1].filled) << "frame 4 was never rendered";
}

}  // namespace
}  // namespace rt
