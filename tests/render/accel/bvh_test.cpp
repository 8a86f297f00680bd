// The BVH: a well-formed tree over every sphere, and, for every CPU
// renderer, byte-identical images with --accel bvh and --accel none on the
// committed scenes (the corpus of uneven sizes too), a 1000-sphere scene
// and scenes built to break it.
#include "render/accel/bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <span>
#include <string>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
#include "render/scalar/sphere_query.h"
#include "test_support.h"

namespace rt {
namespace {

bool contains(const BvhNode& outer, glm::vec3 lo, glm::vec3 hi) {
  return glm::all(glm::lessThanEqual(outer.lo, lo)) && glm::all(glm::lessThanEqual(hi, outer.hi));
}

// Every sphere sits in exactly one leaf, inside every box on its path.
void expectWellFormed(const Bvh& bvh, std::span<const Sphere> spheres, const std::string& label) {
  std::vector<int> seen(spheres.size(), 0);
  std::vector<std::pair<std::uint32_t, int>> stack{{0u, 0}};
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    ASSERT_LT(index, bvh.nodes.size()) << label;
    ASSERT_LE(depth, bvh.depth) << label;
    const BvhNode& node = bvh.nodes[index];
    if (!node.leaf()) {
      for (std::uint32_t child : {node.first, node.first + 1}) {
        EXPECT_TRUE(contains(node, bvh.nodes[child].lo, bvh.nodes[child].hi)) << label << " node " << index;
        stack.push_back({child, depth + 1});
      }
      continue;
    }
    for (std::uint32_t k = node.first; k < node.first + node.count(); ++k) {
      const Sphere& s = spheres[bvh.order[k]];
      ++seen[bvh.order[k]];
      EXPECT_TRUE(contains(node, s.position - glm::vec3(s.radius), s.position + glm::vec3(s.radius))) << label;
    }
  }
  EXPECT_TRUE(std::ranges::all_of(seen, [](int n) { return n == 1; })) << label;
  EXPECT_LE(bvh.depth, kBvhMaxDepth) << label;
}

TEST(Bvh, IsWellFormedOnEveryTestScene) {
  using Names = std::span<const char* const>;
  for (const Names names : {Names(test::kSceneNames), Names(test::kCorpusSceneNames)}) {
    for (const char* name : names) {
      const Scene scene = test::loadNamedScene(name);
      expectWellFormed(buildBvh(scene.spheres), scene.spheres, name);
    }
  }
  for (const auto& [name, scene] : test::adversarialScenes())
    expectWellFormed(buildBvh(scene.spheres), scene.spheres, name);
}

TEST(Bvh, SplitsLargeScenesAndKeepsLeavesSmall) {
  const std::vector<Sphere> spheres = test::randomSpheres(1000, 12, 0.4f);
  const Bvh bvh = buildBvh(spheres);
  EXPECT_GT(bvh.nodes.size(), 1000u / kBvhMaxLeafSize);
  EXPECT_LE(bvh.depth, 30);
  const auto leaves = std::ranges::count_if(bvh.nodes, [](const BvhNode& n) { return n.leaf(); });
  EXPECT_EQ(static_cast<std::size_t>(leaves) * 2 - 1, bvh.nodes.size())
      << "a binary tree: every inner node has two children";
}

// The leaf rule: the GPU renderer's binary walk builds with one sphere per
// leaf, the CPU kernels with up to four (eight where the SAH says so); both
// trees are well formed, and only coincident spheres share a leaf past
// the rule.
TEST(Bvh, LeafRuleBoundsEveryLeafButCoincidentSpheres) {
  const std::vector<Sphere> spheres = test::randomSpheres(1000, 12, 0.4f);
  const auto leafSizes = [&](BvhLeafRule rule, const std::string& label) {
    const Bvh bvh = buildBvh(spheres, rule);
    expectWellFormed(bvh, spheres, label);
    std::vector<std::uint32_t> sizes;
    for (const BvhNode& n : bvh.nodes) {
      if (n.leaf()) sizes.push_back(n.count());
    }
    return sizes;
  };
  const std::vector<std::uint32_t> single = leafSizes(kSingleSphereLeaves, "single");
  const std::vector<std::uint32_t> cpu = leafSizes(kBvhLeaves, "cpu");
  EXPECT_TRUE(std::ranges::all_of(single, [](std::uint32_t n) { return n == 1u; }));
  EXPECT_EQ(single.size(), spheres.size());
  EXPECT_TRUE(std::ranges::all_of(cpu, [](std::uint32_t n) { return n <= kBvhLeaves.sahUpTo; }));
  EXPECT_TRUE(std::ranges::any_of(cpu, [](std::uint32_t n) { return n > 1u; }));
  EXPECT_THROW(buildBvh(spheres, BvhLeafRule{0, 1}), std::invalid_argument);
  EXPECT_THROW(buildBvh(spheres, BvhLeafRule{2, 1}), std::invalid_argument);

  const std::vector<Sphere> pile(3, Sphere{{1, 2, 3}, 0.5f, glm::vec3(1)});
  EXPECT_EQ(buildBvh(pile, kSingleSphereLeaves).nodes[0].count(), 3u) << "coincident spheres cannot be split";
}

TEST(Bvh, CoincidentSpheresShareOneLeaf) {
  const std::vector<Sphere> spheres(9, Sphere{{1, 2, 3}, 0.5f, glm::vec3(1)});
  const Bvh bvh = buildBvh(spheres);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_EQ(bvh.nodes[0].count(), 9u);
  EXPECT_THROW(buildBvh({}), std::invalid_argument);
}

// The scene's pad is at least the pad of any origin its rays can have: a
// sphere's surface (within maxCoordinate) or the camera, nearer or farther out.
TEST(Bvh, SceneTraversalPadCoversEveryOrigin) {
  const Bvh bvh = buildBvh(test::loadNamedScene("random100").spheres);
  for (const float camera : {0.0f, 0.5f * bvh.maxCoordinate, 3.0f * bvh.maxCoordinate}) {
    const float pad = sceneTraversalPad(bvh, camera);
    EXPECT_GE(pad, traversalPad(bvh, bvh.maxCoordinate)) << camera;
    EXPECT_GE(pad, traversalPad(bvh, camera)) << camera;
  }
  EXPECT_GT(sceneTraversalPad(bvh, 3.0f * bvh.maxCoordinate), sceneTraversalPad(bvh, 0.0f));
}

// The build pads the boxes by their own spheres where the scene's extremes
// would widen every box by far more than its spheres need (the ground
// sphere), and keeps the scene's pad where it is the smaller one (uniform
// sizes); padPrice() tells which.
TEST(Bvh, PadsBoxesLocallyWhereOneSphereDwarfsTheRest) {
  const Scene ground = test::groundUnderSmallSpheres();
  const Bvh local = buildBvh(ground.spheres);
  EXPECT_EQ(local.padding, BoxPadding::local);
  EXPECT_EQ(local.pad.radius, 0.0f);
  EXPECT_GT(local.pad.originSlope, 0.0f);
  const Bvh tight = buildBvh(ground.spheres, kBvhLeaves, BoxPadding::scene);
  EXPECT_LT(padPrice(tight, ground.spheres, BoxPadding::local), padPrice(tight, ground.spheres, BoxPadding::scene));
  EXPECT_DOUBLE_EQ(local.price, padPrice(tight, ground.spheres, BoxPadding::local));
  expectWellFormed(local, ground.spheres, "ground, padded locally");
  // Boxes of small spheres only: padded by what those give, far below the
  // scene's pad at the camera (about 6 here).
  const float scenePad = traversalPad(local.maxRadius, local.maxCoordinate, 6.0f);
  EXPECT_GT(scenePad, 5.0f);
  for (std::size_t i = 0; i < local.nodes.size(); ++i) {
    const BvhNode& n = local.nodes[i];
    if (n.leaf() && n.lo.y > -1.0f) {
      EXPECT_LT(n.hi.y - n.lo.y, 2.5f) << "node " << i;
    }
  }
  for (const char* name : {"default", "random100"}) {
    EXPECT_EQ(buildBvh(test::loadNamedScene(name).spheres).padding, BoxPadding::scene) << name;
  }
}

glm::vec3 unitDirection(std::uint32_t i, std::uint32_t salt) {
  return glm::normalize(
      glm::vec3(test::unitNoise(i, salt), test::unitNoise(i, salt + 1), test::unitNoise(i, salt + 2)) - 0.5f);
}

// Either padding finds brute force's nearest sphere for every ray: camera
// rays and rays from sphere surfaces in every direction, on the scenes that
// mix sizes and the rest.
TEST(Bvh, BothPaddingsFindBruteForcesHitForRaysFromAnywhere) {
  for (const auto& [name, scene] : test::adversarialScenes()) {
    for (const BoxPadding padding : {BoxPadding::scene, BoxPadding::local}) {
      const Bvh bvh = buildBvh(scene.spheres, kBvhLeaves, padding);
      int differ = 0;
      for (std::uint32_t i = 0; i < 4000; ++i) {
        const Sphere& from = scene.spheres[i % scene.spheres.size()];
        const glm::vec3 d = unitDirection(i, 11);
        const kernel::Ray<float> ray = i % 2 == 1
                                           ? kernel::Ray<float>{scene.camera.position, d}
                                           : kernel::Ray<float>{from.position + from.radius * d, unitDirection(i, 14)};
        const auto want = kernel::nearestHitOfAll(ray, std::span<const Sphere>(scene.spheres));
        const auto got = kernel::nearestHitInBvh(ray, std::span<const Sphere>(scene.spheres), bvh);
        if (got.sphere != want.sphere) ++differ;
      }
      EXPECT_EQ(differ, 0) << name << (padding == BoxPadding::local ? " local" : " scene");
    }
  }
}

// --accel auto keeps the tree where its price is under half of brute
// force's sphere count, and says which it kept.
TEST(AccelStructure, AutoKeepsTheTreeWhereItsPriceIsUnderHalfTheSpheres) {
  for (const char* name : {"default", "random20", "random1000", "ground500", "random10000"}) {
    const Scene scene = test::loadNamedScene(name);
    AccelStructure accel;
    const Accel ran = accel.prepare(scene.spheres, Accel::auto_);
    const Bvh tree = buildBvh(scene.spheres);
    const bool pays = tree.price < kAutoBvhShare * static_cast<double>(scene.spheres.size());
    EXPECT_EQ(ran, pays ? Accel::bvh : Accel::none) << name;
    EXPECT_EQ(accel.bvh() != nullptr, pays) << name;
    EXPECT_EQ(accel.info().has_value(), pays) << name;
  }
  AccelStructure accel;
  EXPECT_EQ(accel.prepare(test::loadNamedScene("random20").spheres, Accel::auto_), Accel::none)
      << "20 spheres: brute force";
  EXPECT_EQ(accel.prepare(test::loadNamedScene("ground500").spheres, Accel::auto_), Accel::bvh);
  EXPECT_EQ(accel.prepare(test::loadNamedScene("random20").spheres, Accel::bvh), Accel::bvh) << "bvh is kept as asked";
  EXPECT_EQ(accel.prepare(test::loadNamedScene("random1000").spheres, Accel::none), Accel::none);
  EXPECT_EQ(accel.bvh(), nullptr);
}

std::vector<test::NamedScene> exactnessScenes() {
  std::vector<test::NamedScene> scenes;
  for (const char* name : {"default", "random100"}) scenes.push_back({name, test::loadNamedScene(name)});
  for (const char* name : test::kCorpusSceneNames) scenes.push_back({name, test::loadNamedScene(name)});
  for (auto& s : test::adversarialScenes()) scenes.push_back(std::move(s));
  return scenes;
}

class BvhExactness : public ::testing::TestWithParam<RendererKind> {};

// Same renderer, target and lane width: the BVH changes which spheres are
// tested, never which one is hit, so the bytes are the same.
TEST_P(BvhExactness, ImagesAreByteIdenticalToBruteForce) {
  const RendererKind kind = GetParam();
  const auto renderer = makeCpuRenderer(kind);
  for (const auto& [name, scene] : exactnessScenes()) {
    for (const Stage stage : {Stage::original, Stage::optimized}) {
      RenderOptions options = optionsForStage(stage);
      for (const long long frame : {0LL, 25LL}) {
        options.accel = Accel::none;
        const Image brute = test::renderFrame(*renderer, scene, {48, 32}, options, frame);
        options.accel = Accel::bvh;
        const Image bvh = test::renderFrame(*renderer, scene, {48, 32}, options, frame);
        ASSERT_TRUE(renderer->info().accelStructure) << nameOf(kind) << " built no BVH";
        EXPECT_TRUE(std::ranges::equal(brute.pixels(), bvh.pixels()))
            << nameOf(kind) << " " << name << " " << nameOf(stage) << " frame " << frame;
      }
    }
  }
}

// The CPU renderers that answer the spatial query with our structures: the
// Embree reference always traverses its own BVH, so --accel does not reach it.
std::vector<RendererKind> cpuRenderers() {
  std::vector<RendererKind> kinds;
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    const auto kind = static_cast<RendererKind>(i);
    if (cpuRendererBuilt(kind) && definitionOf(kind).kernel != Kernel::embree) kinds.push_back(kind);
  }
  return kinds;
}

INSTANTIATE_TEST_SUITE_P(EveryCpuRenderer, BvhExactness, ::testing::ValuesIn(cpuRenderers()),
                         [](const ::testing::TestParamInfo<RendererKind>& p) { return std::string(nameOf(p.param)); });

}  // namespace
}  // namespace rt
