// The Embree reference renderer: Embree answers the nearest-sphere query,
// our model shades, so its images must agree with the sequential reference
// by the model's rule (docs/render-model.md section 8). Skipped in a build
// without RT_EMBREE, where the renderer must say it is not built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr Extent kSizes[] = {{96, 64}, {101, 37}};
constexpr long long kFrames[] = {0, 30};
constexpr const char* kNotBuilt =
    "renderer 'embree' is not built in this version (configure with RT_EMBREE=ON; Debian: libembree-dev)";

// The renderer, or null where this build has none (the message checked).
std::unique_ptr<Renderer> makeEmbree(const ParallelSettings& settings = {}) {
  try {
    return makeCpuRenderer(RendererKind::embree, settings);
  } catch (const RendererUnavailable& e) {
    EXPECT_STREQ(e.what(), kNotBuilt);
    return nullptr;
  }
}

#define MAKE_EMBREE_OR_SKIP(var, settings)                    \
  const std::unique_ptr<Renderer> var = makeEmbree(settings); \
  if (!(var)) GTEST_SKIP() << "built without RT_EMBREE (no Embree)"

ParallelSettings withLanes(int lanes) {
  ParallelSettings s;
  s.lanes = lanes;
  return s;
}

ParallelSettings withThreads(int threads, Partition partition, int grain) {
  ParallelSettings s;
  s.threads = threads;
  s.partition = partition;
  s.grain = grain;
  return s;
}

// Both algorithms, each with and without the bounce exit.
std::vector<RenderOptions> optionSets() {
  std::vector<RenderOptions> sets;
  for (const Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
    for (const EarlyExitSet exits : {EarlyExitSet{}, optionsForStage(Stage::single_pass).earlyExits}) {
      sets.push_back({algorithm, exits});
    }
  }
  return sets;
}

std::string label(const char* scene, Extent extent, long long frame, const RenderOptions& o) {
  return std::string(scene) + " " + std::to_string(extent.width) + "x" + std::to_string(extent.height) + " frame " +
         std::to_string(frame) + " " + std::string(nameOf(o.algorithm)) + " exits " + o.earlyExits.toString();
}

// Every scene, size, frame and variant against the sequential renderer's image.
void expectAgreesWithSequential(Renderer& embree) {
  SequentialRenderer sequential;
  for (const char* name : test::kSceneNames) {
    const Scene scene = test::loadNamedScene(name);
    for (const Extent extent : kSizes) {
      for (const long long frame : kFrames) {
        for (const RenderOptions& o : optionSets()) {
          const Image want = test::renderFrame(sequential, scene, extent, o, frame);
          const Image got = test::renderFrame(embree, scene, extent, o, frame);
          const ImageAgreement a = compareImages(got, want);
          EXPECT_TRUE(a.agrees()) << label(name, extent, frame, o) << ": " << test::describe(a);
        }
      }
    }
  }
}

TEST(EmbreeRenderer, AgreesWithSequentialAtTheNativePacketWidth) {
  MAKE_EMBREE_OR_SKIP(renderer, ParallelSettings{});
  expectAgreesWithSequential(*renderer);
}

// Embree emulates the widths its ISA does not trace natively (its stream
// path); each must still agree. Width 8 on an AVX2 machine is the native run above.
TEST(EmbreeRenderer, EveryPacketWidthAgreesWithSequential) {
  for (const int lanes : {4, 8, 16}) {
    MAKE_EMBREE_OR_SKIP(renderer, withLanes(lanes));
    if (renderer->info().lanes == makeEmbree()->info().lanes) continue;  // covered by the native test
    SCOPED_TRACE("lanes " + std::to_string(lanes));
    EXPECT_EQ(renderer->info().lanes, lanes);
    expectAgreesWithSequential(*renderer);
  }
}

// Rows are independent and Embree's query is deterministic: how rows and
// tiles are spread over threads changes no bit.
TEST(EmbreeRenderer, ThreadsAndPartitionsGiveIdenticalImages) {
  MAKE_EMBREE_OR_SKIP(one, withThreads(1, Partition::rows, 1));
  const Scene scene = test::loadNamedScene("random100");
  for (const Stage stage : {Stage::original, Stage::optimized}) {
    const RenderOptions o = optionsForStage(stage);
    const Image first = test::renderFrame(*one, scene, {101, 37}, o, 30);
    for (const Partition partition : {Partition::rows, Partition::tiles}) {
      for (const int grain : {1, 3}) {
        const auto many = makeEmbree(withThreads(2, partition, grain));
        const Image image = test::renderFrame(*many, scene, {101, 37}, o, 30);
        EXPECT_TRUE(std::ranges::equal(first.pixels(), image.pixels()))
            << nameOf(stage) << " " << nameOf(partition) << " grain " << grain;
      }
    }
  }
}

// Section 5: without the bounce exit a dead lane is traced again and adds
// exactly 0, so the picture is bit-identical.
TEST(EmbreeRenderer, BounceEarlyExitDoesNotChangeThePicture) {
  MAKE_EMBREE_OR_SKIP(renderer, ParallelSettings{});
  for (const char* name : test::kSceneNames) {
    const Scene scene = test::loadNamedScene(name);
    for (const Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
      const Image with = test::renderFrame(*renderer, scene, {101, 37},
                                           {algorithm, optionsForStage(Stage::single_pass).earlyExits}, 30);
      const Image without = test::renderFrame(*renderer, scene, {101, 37}, {algorithm, EarlyExitSet{}}, 30);
      EXPECT_TRUE(std::ranges::equal(with.pixels(), without.pixels())) << name << " " << nameOf(algorithm);
    }
  }
}

// A second prepare() replaces the scene: no sphere of the first survives.
TEST(EmbreeRenderer, PrepareReplacesTheScene) {
  MAKE_EMBREE_OR_SKIP(renderer, ParallelSettings{});
  SequentialRenderer sequential;
  const RenderOptions o = optionsForStage(Stage::optimized);
  const Scene many = test::loadNamedScene("random100");
  const Scene few = test::loadNamedScene("default");
  (void)test::renderFrame(*renderer, many, {96, 64}, o, 0);
  const ImageAgreement a = compareImages(test::renderFrame(*renderer, few, {96, 64}, o, 0),
                                         test::renderFrame(sequential, few, {96, 64}, o, 0));
  EXPECT_TRUE(a.agrees()) << test::describe(a);
}

TEST(EmbreeRenderer, ReportsItsConfiguration) {
  MAKE_EMBREE_OR_SKIP(renderer, withThreads(2, Partition::tiles, 4));
  const RendererInfo info = renderer->info();
  EXPECT_EQ(info.kind, RendererKind::embree);
  EXPECT_EQ(definitionOf(info.kind).kernel, Kernel::embree);
  EXPECT_EQ(definitionOf(info.kind).scheduler, Scheduler::tbb);
  EXPECT_EQ(info.threads, 2);
  EXPECT_TRUE(info.lanes == 4 || info.lanes == 8 || info.lanes == 16) << info.lanes;
  EXPECT_EQ(info.simdTarget, "embree");
  EXPECT_EQ(info.grain, 4);
  EXPECT_EQ(info.partition, Partition::tiles);
  EXPECT_FALSE(info.accelStructure) << "Embree's BVH is its own; --accel does not apply";
}

TEST(EmbreeRenderer, RejectsALaneCountThatIsNoPacketWidth) {
  MAKE_EMBREE_OR_SKIP(renderer, ParallelSettings{});
  EXPECT_THROW(makeCpuRenderer(RendererKind::embree, withLanes(5)), std::invalid_argument);
}

}  // namespace
}  // namespace rt
