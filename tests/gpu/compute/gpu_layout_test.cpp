// What the GPU renderer uploads for its binary BVH walk
// (src/gpu/compute/gpu_layout.h): each inner node with its children's boxes
// and words, on the committed scenes and the scenes built to break a
// traversal, and the one-leaf tree.
#include "gpu/compute/gpu_layout.h"

#include <gtest/gtest.h>

#include "render/accel/accel_scenes.h"
#include "test_support.h"

namespace rt::test {
namespace {

std::vector<NamedScene> layoutScenes() {
  std::vector<NamedScene> scenes = adversarialScenes();
  for (const char* name : kSceneNames) scenes.push_back({name, loadNamedScene(name)});
  return scenes;
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
