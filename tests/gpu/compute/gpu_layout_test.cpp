// What the GPU renderer uploads for its binary BVH walk
// (src/gpu/compute/gpu_layout.h): each inner node with its children's boxes
// and words, numbered depth first with only the inner nodes, on the committed scenes and the scenes built to break a
// traversal, and the one-leaf tree.
#include "gpu/compute/gpu_layout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "test_support.h"

namespace rt::test {
namespace {

std::vector<NamedScene> layoutScenes() {
  std::vector<NamedScene> scenes = adversarialScenes();
  for (const char* name : kSceneNames) scenes.push_back({name, loadNamedScene(name)});
  return scenes;
}

// Walks the GPU's nodes from its root beside the tree's: every GPU node is
// one inner node of the tree, with its children's boxes and words, and
// every inner node is there once. Checks on the way that the left child
// comes right after its parent (depth first, left subtree first).
void expectSameTree(const Bvh& bvh, std::span<const gpu::GpuBinaryNode> nodes, const std::string& name) {
  std::vector<int> seen(nodes.size(), 0);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pending{{0u, 0u}};  // (bvh node, gpu node)
  std::size_t inner = 0;
  while (!pending.empty()) {
    const auto [index, gpuIndex] = pending.back();
    pending.pop_back();
    ASSERT_LT(gpuIndex, nodes.size()) << name;
    ++seen[gpuIndex];
    ++inner;
    const BvhNode& left = bvh.nodes[bvh.nodes[index].first];
    const BvhNode& right = bvh.nodes[bvh.nodes[index].first + 1];
    const gpu::GpuBinaryNode& g = nodes[gpuIndex];
    EXPECT_EQ(g.lo0, left.lo) << name;
    EXPECT_EQ(g.hi0, left.hi) << name;
    EXPECT_EQ(g.lo1, right.lo) << name;
    EXPECT_EQ(g.hi1, right.hi) << name;
    EXPECT_EQ(g.count0, left.leaf() ? left.count() : 0u) << name;
    EXPECT_EQ(g.count1, right.leaf() ? right.count() : 0u) << name;
    if (left.leaf()) {
      EXPECT_EQ(g.child0, left.first) << name;
    } else {
      EXPECT_EQ(g.child0, gpuIndex + 1) << name;
      pending.emplace_back(bvh.nodes[index].first, g.child0);
    }
    if (right.leaf()) {
      EXPECT_EQ(g.child1, right.first) << name;
    } else {
      pending.emplace_back(bvh.nodes[index].first + 1, g.child1);
    }
  }
  EXPECT_EQ(inner, nodes.size()) << name;
  EXPECT_TRUE(std::ranges::all_of(seen, [](int n) { return n == 1; })) << name;
}

TEST(GpuBinaryNodes, EachInnerNodeHoldsItsChildrensBoxesAndWords) {
  for (const auto& [name, scene] : layoutScenes()) {
    for (const BvhLeafRule leaves : {kBvhLeaves, kSingleSphereLeaves}) {
      const Bvh bvh = buildBvh(scene.spheres, leaves);
      if (bvh.nodes[0].leaf()) continue;  // the next test's case
      const std::vector<gpu::GpuBinaryNode> nodes = gpu::toGpuBinaryNodes(bvh, 0.0f);
      EXPECT_EQ(nodes.size(),
                static_cast<std::size_t>(std::ranges::count_if(bvh.nodes, [](const BvhNode& n) { return !n.leaf(); })))
          << name;
      expectSameTree(bvh, nodes, name);
    }
  }
}

// The boxes come widened by the pad on every side; the words stay.
TEST(GpuBinaryNodes, EachChildsBoxIsWidenedByThePad) {
  const Scene scene = loadNamedScene("random100");
  const Bvh bvh = buildBvh(scene.spheres, kSingleSphereLeaves);
  const float pad = 0.25f;
  const std::vector<gpu::GpuBinaryNode> tight = gpu::toGpuBinaryNodes(bvh, 0.0f);
  const std::vector<gpu::GpuBinaryNode> padded = gpu::toGpuBinaryNodes(bvh, pad);
  ASSERT_EQ(tight.size(), padded.size());
  for (std::size_t i = 0; i < tight.size(); ++i) {
    EXPECT_EQ(padded[i].lo0, tight[i].lo0 - pad) << i;
    EXPECT_EQ(padded[i].hi0, tight[i].hi0 + pad) << i;
    EXPECT_EQ(padded[i].lo1, tight[i].lo1 - pad) << i;
    EXPECT_EQ(padded[i].hi1, tight[i].hi1 + pad) << i;
    EXPECT_EQ(padded[i].child0, tight[i].child0) << i;
    EXPECT_EQ(padded[i].child1, tight[i].child1) << i;
    EXPECT_EQ(padded[i].count0, tight[i].count0) << i;
    EXPECT_EQ(padded[i].count1, tight[i].count1) << i;
  }
}

// A scene of one sphere is a tree of one leaf: the root holds it twice.
TEST(GpuBinaryNodes, ATreeOfOneLeafIsARootWithThatLeafTwice) {
  Scene scene = loadNamedScene("default");
  scene.spheres.resize(1);
  const Bvh bvh = buildBvh(scene.spheres);
  ASSERT_TRUE(bvh.nodes[0].leaf());
  const std::vector<gpu::GpuBinaryNode> nodes = gpu::toGpuBinaryNodes(bvh, 0.0f);
  ASSERT_EQ(nodes.size(), 1u);
  const gpu::GpuBinaryNode root = nodes[0];
  EXPECT_EQ(root.count0, 1u);
  EXPECT_EQ(root.count1, 1u);
  EXPECT_EQ(root.child0, bvh.nodes[0].first);
  EXPECT_EQ(root.lo1, bvh.nodes[0].lo);
}

}  // namespace
}  // namespace rt::test
