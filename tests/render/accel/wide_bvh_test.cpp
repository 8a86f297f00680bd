// The wide BVH and the SIMD kernel's traversals of it: a well-formed tree
// over every sphere, and byte-identical images to brute force for every
// traversal, threshold, Highway target, algorithm and early-exit set, with
// and without counters, on the scenes that the binary BVH is tested on.
#include "render/accel/wide_bvh.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
#include "render/simd/packet_kernels.h"
#include "test_support.h"

namespace rt {
namespace {

struct WideCheck {
  std::vector<int> seen;
  std::uint32_t largestLeaf = 0;
};

// Every sphere sits in exactly one leaf, inside its box and every box on its path.
void checkSubtree(const WideBvh& wide, std::span<const Sphere> spheres, std::uint32_t node, int depth, WideCheck& check,
                  const std::string& label) {
  ASSERT_LT(node, wide.nodes.size()) << label;
  ASSERT_LE(depth, wide.depth) << label;
  const WideBvhNode& n = wide.nodes[node];
  ASSERT_GE(n.childCount, 1u) << label;
  ASSERT_LE(n.childCount, static_cast<std::uint32_t>(kWideBvhWidth)) << label;
  for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(kWideBvhWidth); ++j) {
    const glm::vec3 lo{n.bounds[WideBvhNode::kLoX][j], n.bounds[WideBvhNode::kLoY][j], n.bounds[WideBvhNode::kLoZ][j]};
    const glm::vec3 hi{n.bounds[WideBvhNode::kHiX][j], n.bounds[WideBvhNode::kHiY][j], n.bounds[WideBvhNode::kHiZ][j]};
    if (j >= n.childCount) {  // an empty slot: a box no ray enters
      EXPECT_TRUE(glm::all(glm::greaterThan(lo, hi))) << label << " node " << node << " slot " << j;
      continue;
    }
    if (!n.child[j].leaf()) {
      checkSubtree(wide, spheres, n.child[j].node(), depth + 1, check, label);
      continue;
    }
    const WideChild leaf = n.child[j];
    ASSERT_LT(leaf.block(), wide.leaves.size()) << label;
    check.largestLeaf = std::max(check.largestLeaf, leaf.count());
    const LeafBlock& block = wide.leaves[leaf.block()];
    for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(kWideBvhWidth); ++k) {
      const std::int32_t slotIndex = wide.index[leaf.block() * kWideBvhWidth + k];
      if (k >= leaf.count()) {  // an unused slot: a sphere no ray hits
        EXPECT_EQ(slotIndex, -1) << label;
        EXPECT_LT(block.radiusSquared[k], 0.0f) << label;
        continue;
      }
      const auto index = static_cast<std::size_t>(slotIndex);
      ASSERT_LT(index, spheres.size()) << label;
      const Sphere& s = spheres[index];
      ++check.seen[index];
      EXPECT_EQ(block.centerX[k], s.position.x) << label;
      EXPECT_EQ(block.centerY[k], s.position.y) << label;
      EXPECT_EQ(block.centerZ[k], s.position.z) << label;
      EXPECT_EQ(block.radiusSquared[k], s.radius * s.radius) << label;
      EXPECT_TRUE(glm::all(glm::lessThanEqual(lo, s.position - glm::vec3(s.radius))) &&
                  glm::all(glm::lessThanEqual(s.position + glm::vec3(s.radius), hi)))
          << label << " sphere " << index << " outside its leaf's box";
    }
  }
}

std::vector<test::NamedScene> wideScenes() {
  std::vector<test::NamedScene> scenes;
  for (const char* name : {"default", "random100"}) scenes.push_back({name, test::loadNamedScene(name)});
  for (const char* name : test::kCorpusSceneNames) scenes.push_back({name, test::loadNamedScene(name)});
  for (auto& s : test::adversarialScenes()) scenes.push_back(std::move(s));
  // More coincident spheres than a vector holds: one leaf, tested a vector at a time.
  std::vector<Sphere> pile = test::randomSpheres(60, 6, 0.5f);
  for (int i = 0; i < 19; ++i)
    pile.push_back({{0.0f, 0.0f, 0.0f}, 1.0f + 0.01f * static_cast<float>(i % 3), {1, 0, 0}});
  scenes.push_back({"coincident-pile", test::withSpheres(pile)});
  return scenes;
}

TEST(WideBvh, IsWellFormedOnEveryTestScene) {
  for (const auto& [name, scene] : wideScenes()) {
    const Bvh bvh = buildBvh(scene.spheres);
    const WideBvh wide = buildWideBvh(bvh, scene.spheres);
    WideCheck check{std::vector<int>(scene.spheres.size(), 0)};
    checkSubtree(wide, scene.spheres, 0, 0, check, name);
    EXPECT_TRUE(std::ranges::all_of(check.seen, [](int n) { return n == 1; })) << name;
    EXPECT_LE(wide.depth, bvh.depth) << name;
    EXPECT_LE(check.largestLeaf, static_cast<std::uint32_t>(kWideBvhWidth)) << name;
    EXPECT_EQ(wide.index.size(), wide.leaves.size() * kWideBvhWidth) << name;
  }
}

TEST(WideBvh, CollapsesALargeTreeIntoFewerLevels) {
  const std::vector<Sphere> spheres = test::randomSpheres(4000, 30, 0.3f);
  const Bvh bvh = buildBvh(spheres);
  const WideBvh wide = buildWideBvh(bvh, spheres);
  EXPECT_LT(wide.depth * 2, bvh.depth);
  EXPECT_LT(wide.nodes.size() * 4, bvh.nodes.size());
}

// 200 coincident spheres share one binary leaf; the wide tree splits them
// into full leaves under nodes of the same box, two levels of them.
TEST(WideBvh, PilesOfCoincidentSpheresBecomeNodesOfFullLeaves) {
  std::vector<Sphere> pile(200, Sphere{{1.0f, 2.0f, 3.0f}, 0.5f, {1, 0, 0}});
  const Bvh bvh = buildBvh(pile);
  ASSERT_EQ(bvh.nodes.size(), 1u) << "one binary leaf";
  const WideBvh wide = buildWideBvh(bvh, pile);
  WideCheck check{std::vector<int>(pile.size(), 0)};
  checkSubtree(wide, pile, 0, 0, check, "pile");
  EXPECT_TRUE(std::ranges::all_of(check.seen, [](int n) { return n == 1; }));
  EXPECT_EQ(check.largestLeaf, static_cast<std::uint32_t>(kWideBvhWidth));
  EXPECT_EQ(wide.depth, 2);
}

// The collapse fills its leaf blocks on the pool: the tree, blocks and
// index are the one-thread collapse's, bit for bit, with any number of
// threads (that one thread's tree is the renderers': their images are
// checked against brute force).
void expectReferenceWideTree(std::span<const Sphere> spheres, const std::string& label) {
  const Bvh bvh = buildBvh(spheres);
  const WideBvh expected = tbb::task_arena(1).execute([&] { return buildWideBvh(bvh, spheres); });
  for (const int threads : {2, 3}) {
    tbb::task_arena arena(threads);
    const WideBvh wide = arena.execute([&] { return buildWideBvh(bvh, spheres); });
    const std::string where = label + " threads " + std::to_string(threads);
    ASSERT_EQ(wide.nodes.size(), expected.nodes.size()) << where;
    for (std::size_t i = 0; i < wide.nodes.size(); ++i) {
      const WideBvhNode &a = expected.nodes[i], &b = wide.nodes[i];
      ASSERT_EQ(std::memcmp(&a.bounds, &b.bounds, sizeof a.bounds), 0) << where << " node " << i;
      ASSERT_EQ(std::memcmp(&a.child, &b.child, sizeof a.child), 0) << where << " node " << i;
      ASSERT_EQ(a.childCount, b.childCount) << where << " node " << i;
    }
    ASSERT_EQ(wide.leaves.size(), expected.leaves.size()) << where;
    EXPECT_EQ(std::memcmp(wide.leaves.data(), expected.leaves.data(), wide.leaves.size() * sizeof(LeafBlock)), 0)
        << where;
    EXPECT_EQ(wide.index, expected.index) << where;
    EXPECT_EQ(wide.depth, expected.depth) << where;
  }
}

TEST(WideBvh, IsTheSameTreeOnAnyNumberOfThreads) {
  for (const char* name : test::kSceneNames) expectReferenceWideTree(test::loadNamedScene(name).spheres, name);
  for (const auto& [name, scene] : test::adversarialScenes()) expectReferenceWideTree(scene.spheres, name);
  expectReferenceWideTree(test::randomSpheres(100000, 60, 0.4f), "random 100000");
  std::vector<Sphere> piles = test::randomSpheres(20000, 30, 0.5f);
  for (std::size_t i = 0; i < piles.size(); ++i) piles[i].position = piles[i / 70 * 70].position;
  expectReferenceWideTree(piles, "piles of 70");
}

struct TraversalCase {
  Traversal traversal;
  int threshold;  // RenderOptions::hybridThreshold
};

std::string describe(const TraversalCase& c) {
  return std::string(nameOf(c.traversal)) +
         (c.traversal == Traversal::hybrid ? " threshold " + std::to_string(c.threshold) : "");
}

// Hybrid at 1 lane (almost always packets), the default, and 16 (always single rays).
const TraversalCase kTraversals[] = {{Traversal::packet, 0},
                                     {Traversal::single, 0},
                                     {Traversal::hybrid, 1},
                                     {Traversal::hybrid, RenderOptions::kDefaultHybridThreshold},
                                     {Traversal::hybrid, 16}};

using TargetAndRenderer = std::tuple<std::int64_t, RendererKind>;

class TraversalExactness : public ::testing::TestWithParam<TargetAndRenderer> {};

// The traversal changes which boxes a ray visits, never which sphere it
// hits: the bytes are brute force's, counters on or off.
TEST_P(TraversalExactness, ImagesAreByteIdenticalToBruteForce) {
  const auto [target, kind] = GetParam();
  const simd::ScopedTargetOverride force(target);
  const auto renderer = makeCpuRenderer(kind);
  for (const auto& [name, scene] : wideScenes()) {
    for (const Stage stage : {Stage::original, Stage::single_pass, Stage::optimized}) {
      RenderOptions options = optionsForStage(stage);
      const Image brute = test::renderFrame(*renderer, scene, {40, 24}, options, 25);
      options.accel = Accel::bvh;
      for (const TraversalCase& c : kTraversals) {
        options.traversal = c.traversal;
        options.hybridThreshold = c.threshold;
        options.counters = c.threshold == 16;
        const Image image = test::renderFrame(*renderer, scene, {40, 24}, options, 25);
        ASSERT_EQ(renderer->info().traversal, c.traversal);
        EXPECT_TRUE(std::ranges::equal(brute.pixels(), image.pixels()))
            << nameOf(kind) << " " << simd::targetName(target) << " " << name << " " << nameOf(stage) << " "
            << describe(c);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryTarget, TraversalExactness,
                         ::testing::Combine(::testing::ValuesIn(simd::availableTargets()),
                                            ::testing::Values(RendererKind::simd_tbb, RendererKind::simd_only)),
                         [](const ::testing::TestParamInfo<TargetAndRenderer>& p) {
                           return simd::targetName(std::get<0>(p.param)) + "_" +
                                  std::string(nameOf(std::get<1>(p.param)));
                         });

}  // namespace
}  // namespace rt
