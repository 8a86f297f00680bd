// The parallel BVH build gives the tree the one-thread builder gave
// (reference_bvh.h): the same nodes bit for bit, in the same layout, the
// same Bvh::order, depth and traversal pad inputs, on every committed
// scene, the scenes built to break a BVH, and large generated scenes that
// reach the build's parallel paths; with one thread and with several.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "render/accel/bvh.h"
#include "render/accel/reference_bvh.h"
#include "test_support.h"

namespace rt {
namespace {

void expectSameTree(const Bvh& expected, const Bvh& actual, const std::string& label) {
  ASSERT_EQ(expected.nodes.size(), actual.nodes.size()) << label;
  const auto differs = std::ranges::mismatch(expected.nodes, actual.nodes, [](const BvhNode& a, const BvhNode& b) {
    return std::memcmp(&a, &b, sizeof(BvhNode)) == 0;
  });
  EXPECT_EQ(differs.in1, expected.nodes.end())
      << label << ": node " << (differs.in1 - expected.nodes.begin()) << " differs";
  EXPECT_EQ(expected.order, actual.order) << label << ": the order differs";
  EXPECT_EQ(expected.depth, actual.depth) << label;
  EXPECT_EQ(expected.maxRadius, actual.maxRadius) << label;
  EXPECT_EQ(expected.maxCoordinate, actual.maxCoordinate) << label;
}

// The reference builds tight boxes: the trees are compared with the scene's
// padding, and the padding the build would choose changes no sphere's place.
Bvh buildWithThreads(std::span<const Sphere> spheres, int threads) {
  tbb::task_arena arena(threads);
  return arena.execute([&] { return buildBvh(spheres, kBvhLeaves, BoxPadding::scene); });
}

// Every thread count builds the reference's tree.
void expectReferenceTree(std::span<const Sphere> spheres, const std::string& label) {
  const Bvh expected = test::referenceBvh(spheres);
  for (const int threads : {1, 2, 3, 8}) {
    expectSameTree(expected, buildWithThreads(spheres, threads), label + " threads " + std::to_string(threads));
  }
  const Bvh chosen = buildBvh(spheres);
  EXPECT_EQ(chosen.order, expected.order) << label << " (" << nameOf(chosen.padding) << " padding)";
  EXPECT_EQ(chosen.nodes.size(), expected.nodes.size()) << label;
}

TEST(BvhBuild, MatchesTheReferenceOnEveryCommittedScene) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(RT_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    const Scene scene = loadScene(entry.path().string());
    expectReferenceTree(scene.spheres, entry.path().filename().string());
    ++scenes;
  }
  EXPECT_GE(scenes, 5);
}

TEST(BvhBuild, MatchesTheReferenceOnAdversarialScenes) {
  for (const auto& [name, scene] : test::adversarialScenes()) expectReferenceTree(scene.spheres, name);
  expectReferenceTree(std::vector<Sphere>(1, Sphere{{1, 2, 3}, 0.5f, glm::vec3(1)}), "one sphere");
  expectReferenceTree(std::vector<Sphere>(9, Sphere{{1, 2, 3}, 0.5f, glm::vec3(1)}), "nine coincident");
}

// 100,000 spheres: long enough that the build bins in parallel chunks and
// splits into parallel subtrees.
TEST(BvhBuild, MatchesTheReferenceOnAHundredThousandSpheres) {
  expectReferenceTree(test::randomSpheres(100000, 60, 0.4f), "random 100000");
}

// Large scenes of the shapes that stress the splits: every centre in one
// plane (an axis that cannot be split), piles of coincident spheres (nodes
// over the leaf size that stay leaves), a long thin line with a few huge
// spheres, and one pile too large to split at all.
TEST(BvhBuild, MatchesTheReferenceOnLargeDegenerateScenes) {
  std::vector<Sphere> plane = test::randomSpheres(80000, 40, 0.3f);
  for (Sphere& s : plane) s.position.y = 0.0f;
  expectReferenceTree(plane, "plane");

  std::vector<Sphere> piles = test::randomSpheres(90000, 30, 0.5f);
  for (std::size_t i = 0; i < piles.size(); ++i) piles[i].position = piles[i / 7 * 7].position;
  expectReferenceTree(piles, "piles of 7");

  std::vector<Sphere> line = test::randomSpheres(70000, 1000, 0.01f);
  for (std::size_t i = 0; i < line.size(); ++i) {
    line[i].position.y = line[i].position.z = 0.0f;
    if (i % 10000 == 0) line[i].radius = 200.0f;
  }
  expectReferenceTree(line, "line");

  expectReferenceTree(std::vector<Sphere>(70000, Sphere{{-1, 0, 2}, 1, glm::vec3(1)}), "one pile");
}

// The check above can fail: a tree with two spheres of a leaf swapped, or
// one box nudged by an ulp, is told apart.
TEST(BvhBuild, TheComparisonSeesOneChange) {
  const std::vector<Sphere> spheres = test::randomSpheres(1000, 12, 0.4f);
  const Bvh expected = test::referenceBvh(spheres);
  Bvh swapped = buildBvh(spheres, kBvhLeaves, BoxPadding::scene);
  std::swap(swapped.order[0], swapped.order[1]);
  EXPECT_NONFATAL_FAILURE(expectSameTree(expected, swapped, "swapped"), "the order differs");
  Bvh nudged = buildBvh(spheres, kBvhLeaves, BoxPadding::scene);
  nudged.nodes.back().hi.x = std::nextafter(nudged.nodes.back().hi.x, 1e30f);
  EXPECT_NONFATAL_FAILURE(expectSameTree(expected, nudged, "nudged"), "differs");
}

TEST(BvhBuild, FitsItsNodesAndRecordsItsTime) {
  const std::vector<Sphere> spheres = test::randomSpheres(20000, 30, 0.4f);
  const Bvh bvh = buildBvh(spheres);
  EXPECT_EQ(bvh.nodes.capacity(), bvh.nodes.size());
  EXPECT_GT(bvh.buildMs, 0.0);
}

// Not a test: the build's wall time at a million spheres (and more with
// RT_BVH_TIMING_SPHERES), with one thread and with all, for the report.
// Run with --gtest_also_run_disabled_tests --gtest_filter='*Timing*'.
TEST(BvhBuild, DISABLED_Timing) {
  const char* env = std::getenv("RT_BVH_TIMING_SPHERES");
  const auto count = static_cast<std::uint32_t>(env ? std::stoul(env) : 1000000);
  const std::vector<Sphere> spheres = test::randomSpheres(count, 300, 0.6f);
  for (const int threads : {1, tbb::this_task_arena::max_concurrency()}) {
    for (int rep = 0; rep < 3; ++rep) {
      const Bvh bvh = buildWithThreads(spheres, threads);
      std::printf("%u spheres, %d threads: buildBvh %.1f ms, %zu nodes\n", count, threads, bvh.buildMs,
                  bvh.nodes.size());
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const Bvh reference = test::referenceBvh(spheres);
  std::printf("reference builder: %.1f ms\n",
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace
}  // namespace rt
