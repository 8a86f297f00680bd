// What the GPU renderer uploads for its BVH walks (src/gpu/compute/gpu_layout.h):
// the binary nodes with their children's boxes, and the compressed wide
// nodes whose decoded boxes must hold the exact ones (docs/render-model.md
// section 3), on the committed scenes and the scenes built to break a traversal.
#include "gpu/compute/gpu_layout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "render/accel/accel_scenes.h"
#include "test_support.h"

namespace rt::test {
namespace {

std::vector<NamedScene> layoutScenes() {
  std::vector<NamedScene> scenes = adversarialScenes();
  for (const char* name : kSceneNames) scenes.push_back({name, loadNamedScene(name)});
  return scenes;
}

TEST(GpuWideNodes, DecodedBoxesHoldTheExactOnesWithinTwoGridSteps) {
  for (const auto& [name, scene] : layoutScenes()) {
    const Bvh bvh = buildBvh(scene.spheres);
    const WideBvh wide = buildWideBvh(bvh, scene.spheres);
    const std::vector<gpu::GpuWideNode> nodes = gpu::toGpuWideNodes(wide);
    ASSERT_EQ(nodes.size(), wide.nodes.size()) << name;
    for (std::size_t n = 0; n < nodes.size(); ++n) {
      const gpu::GpuWideNode& g = nodes[n];
      ASSERT_EQ(g.exponentsAndCount >> 24, wide.nodes[n].childCount) << name;
      for (int axis = 0; axis < 3; ++axis) {
        const int exponent = static_cast<int>((g.exponentsAndCount >> (8 * axis)) & 0xffu) - 127;
        const float scale = std::ldexp(1.0f, exponent);
        for (std::uint32_t c = 0; c < wide.nodes[n].childCount; ++c) {
          const float lo = wide.nodes[n].bounds[WideBvhNode::kLoX + axis][c];
          const float hi = wide.nodes[n].bounds[WideBvhNode::kHiX + axis][c];
          const float decodedLo = gpu::decodePlane(g.origin[axis], g.planes[WideBvhNode::kLoX + axis][c], scale);
          const float decodedHi = gpu::decodePlane(g.origin[axis], g.planes[WideBvhNode::kHiX + axis][c], scale);
          EXPECT_LE(decodedLo, lo) << name << " node " << n << " child " << c << " axis " << axis;
          EXPECT_GE(decodedHi, hi) << name << " node " << n << " child " << c << " axis " << axis;
          // Not trivially: the grid is fine enough to keep the boxes tight.
          EXPECT_LE(lo - decodedLo, 2 * scale) << name << " node " << n << " child " << c;
          EXPECT_LE(decodedHi - hi, 2 * scale) << name << " node " << n << " child " << c;
          EXPECT_EQ(g.child[c], wide.nodes[n].child[c].bits);
        }
      }
    }
  }
}

TEST(GpuBinaryNodes, EachInnerNodeHoldsItsChildrensBoxesAndWords) {
  for (const auto& [name, scene] : layoutScenes()) {
    const Bvh bvh = buildBvh(scene.spheres);
    const std::vector<gpu::GpuBinaryNode> nodes = gpu::toGpuBinaryNodes(bvh);
    ASSERT_EQ(nodes.size(), bvh.nodes.size());
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
      if (bvh.nodes[i].leaf()) continue;
      const BvhNode& left = bvh.nodes[bvh.nodes[i].first];
      const BvhNode& right = bvh.nodes[bvh.nodes[i].first + 1];
      EXPECT_EQ(nodes[i].lo0, left.lo);
      EXPECT_EQ(nodes[i].hi1, right.hi);
      EXPECT_EQ(nodes[i].count0, left.leaf() ? left.count() : 0u) << name;
      EXPECT_EQ(nodes[i].child1, right.leaf() ? right.first : bvh.nodes[i].first + 1) << name;
    }
  }
}

// A scene of one sphere is a tree of one leaf: the root holds it twice.
TEST(GpuBinaryNodes, ATreeOfOneLeafIsARootWithThatLeafTwice) {
  Scene scene = loadNamedScene("default");
  scene.spheres.resize(1);
  const Bvh bvh = buildBvh(scene.spheres);
  ASSERT_TRUE(bvh.nodes[0].leaf());
  const gpu::GpuBinaryNode root = gpu::toGpuBinaryNodes(bvh)[0];
  EXPECT_EQ(root.count0, 1u);
  EXPECT_EQ(root.count1, 1u);
  EXPECT_EQ(root.child0, bvh.nodes[0].first);
  EXPECT_EQ(root.lo1, bvh.nodes[0].lo);
}

}  // namespace
}  // namespace rt::test
