#pragma once
// The wide BVH collapse as it was before its leaf blocks were filled on
// oneTBB: kept as the reference that wide_bvh_test.cpp holds
// rt::buildWideBvh to (the same nodes, leaf blocks and index).
#include <algorithm>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "render/accel/wide_bvh.h"

namespace rt::test {
namespace reference_wide_bvh {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A binary node's spheres are one range of Bvh::order (the build partitions
// in place), which a leaf of the wide tree can take whole.
struct Subtree {
  std::uint32_t first = 0;
  std::uint32_t count = 0;
};

inline float halfArea(const BvhNode& n) {
  const glm::vec3 e = n.hi - n.lo;
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

class Collapser {
 public:
  Collapser(const Bvh& bvh, std::span<const Sphere> spheres) : bvh_(bvh), spheres_(spheres) {
    subtrees_.resize(bvh.nodes.size());
    measure(0);
  }

  WideBvh collapse() && {
    wide_.nodes.emplace_back();
    fill(0, {0u}, 0);
    return std::move(wide_);
  }

 private:
  Subtree measure(std::uint32_t node) {
    const BvhNode& n = bvh_.nodes[node];
    if (n.leaf()) return subtrees_[node] = {n.first, n.count()};
    const Subtree left = measure(n.first);
    const Subtree right = measure(n.first + 1);
    return subtrees_[node] = {left.first, left.count + right.count};
  }

  // A binary node becomes a leaf of the wide tree when one vector pass tests all its spheres.
  [[nodiscard]] bool opens(std::uint32_t node) const {
    return !bvh_.nodes[node].leaf() && subtrees_[node].count > kWideBvhWidth;
  }

  // Wide node `wide` takes the binary nodes `slots` and, while it has room,
  // replaces the one of largest surface (the likeliest to be entered) by its
  // two children.
  void fill(std::size_t wide, std::vector<std::uint32_t> slots, int depth) {
    wide_.depth = std::max(wide_.depth, depth);
    if (slots.size() == 1 && opens(slots[0])) slots = {bvh_.nodes[slots[0]].first, bvh_.nodes[slots[0]].first + 1};
    while (slots.size() < kWideBvhWidth) {
      auto best = slots.end();
      for (auto it = slots.begin(); it != slots.end(); ++it) {
        if (opens(*it) && (best == slots.end() || halfArea(bvh_.nodes[*it]) > halfArea(bvh_.nodes[*best]))) best = it;
      }
      if (best == slots.end()) break;
      const std::uint32_t left = bvh_.nodes[*best].first;
      *best = left;
      slots.insert(best + 1, left + 1);
    }
    WideBvhNode node = emptyNode();
    node.childCount = static_cast<std::uint32_t>(slots.size());
    std::vector<std::pair<std::size_t, std::uint32_t>> inner;
    for (std::size_t k = 0; k < slots.size(); ++k) {
      const BvhNode& b = bvh_.nodes[slots[k]];
      setBox(node, k, b.lo, b.hi);
      if (opens(slots[k])) {
        inner.emplace_back(k, slots[k]);
      } else {
        node.child[k] = spheresChild(subtrees_[slots[k]], b.lo, b.hi, depth + 1);
      }
    }
    for (const auto& [k, binary] : inner) {
      node.child[k] = WideChild::inner(static_cast<std::uint32_t>(wide_.nodes.size()));
      wide_.nodes.emplace_back();
      fill(node.child[k].node(), {binary}, depth + 1);
    }
    wide_.nodes[wide] = node;
  }

  static WideBvhNode emptyNode() {
    WideBvhNode node{};
    for (int a = 0; a < 3; ++a) {
      node.bounds[WideBvhNode::kLoX + a].fill(kInf);
      node.bounds[WideBvhNode::kHiX + a].fill(-kInf);
    }
    return node;
  }

  static void setBox(WideBvhNode& node, std::size_t slot, const glm::vec3& lo, const glm::vec3& hi) {
    for (int a = 0; a < 3; ++a) {
      node.bounds[WideBvhNode::kLoX + a][slot] = lo[a];
      node.bounds[WideBvhNode::kHiX + a][slot] = hi[a];
    }
  }

  // A range of Bvh::order under one box: one leaf, or, for a pile of more
  // coincident spheres than a leaf holds, a node of leaves (and of such
  // nodes) under the same box.
  WideChild spheresChild(Subtree s, const glm::vec3& lo, const glm::vec3& hi, int depth) {
    if (s.count <= kWideBvhWidth) return addLeaf(s);
    wide_.depth = std::max(wide_.depth, depth);
    const auto index = static_cast<std::uint32_t>(wide_.nodes.size());
    wide_.nodes.emplace_back();
    WideBvhNode node = emptyNode();
    std::uint32_t part = kWideBvhWidth;  // full leaves, or full subtrees of them
    while (part * kWideBvhWidth < s.count) part *= kWideBvhWidth;
    for (std::uint32_t first = s.first; first < s.first + s.count; first += part) {
      const std::uint32_t slot = node.childCount++;
      setBox(node, slot, lo, hi);
      node.child[slot] = spheresChild({first, std::min(part, s.first + s.count - first)}, lo, hi, depth + 1);
    }
    wide_.nodes[index] = node;
    return WideChild::inner(index);
  }

  WideChild addLeaf(Subtree s) {
    const auto block = static_cast<std::uint32_t>(wide_.leaves.size());
    if (block > WideChild::kBlockMask) throw std::length_error("wide BVH: too many leaves");
    LeafBlock leaf{};
    leaf.radiusSquared.fill(-1.0f);
    for (std::uint32_t k = 0; k < kWideBvhWidth; ++k) {
      if (k >= s.count) {
        wide_.index.push_back(-1);
        continue;
      }
      const std::uint32_t i = bvh_.order[s.first + k];
      const Sphere& sphere = spheres_[i];
      leaf.centerX[k] = sphere.position.x;
      leaf.centerY[k] = sphere.position.y;
      leaf.centerZ[k] = sphere.position.z;
      leaf.radiusSquared[k] = sphere.radius * sphere.radius;  // as the kernels' SphereArrays
      wide_.index.push_back(static_cast<std::int32_t>(i));
    }
    wide_.leaves.push_back(leaf);
    return WideChild::leafOf(block, s.count);
  }

  const Bvh& bvh_;
  std::span<const Sphere> spheres_;
  std::vector<Subtree> subtrees_;
  WideBvh wide_;
};

}  // namespace reference_wide_bvh

// rt::buildWideBvh's tree as the one-thread collapse made it (buildMs left 0).
inline WideBvh referenceWideBvh(const Bvh& bvh, std::span<const Sphere> spheres) {
  return reference_wide_bvh::Collapser(bvh, spheres).collapse();
}

}  // namespace rt::test
