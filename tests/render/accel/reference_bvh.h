#pragma once
// The binary BVH builder as it was before it ran on oneTBB: one thread,
// binned SAH over an index array. Kept as the reference that
// reference_bvh_test.cpp holds rt::buildBvh to: the same nodes, bit for
// bit, and the same Bvh::order.
#include <algorithm>
#include <array>
#include <glm/common.hpp>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "render/accel/bvh.h"

namespace rt::test {
namespace reference_bvh {

constexpr int kBins = 16;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Box {
  glm::vec3 lo{kInf};
  glm::vec3 hi{-kInf};

  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  void grow(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  [[nodiscard]] float halfArea() const {
    if (lo.x > hi.x) return 0.0f;
    const glm::vec3 e = hi - lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

struct Bin {
  Box bounds;
  std::uint32_t count = 0;
};

struct Split {
  int axis = -1;
  int bin = 0;  // spheres in bins [0, bin] go left
  float cost = kInf;
};

// Builds top-down; the sphere boxes and centres are computed once.
class Builder {
 public:
  explicit Builder(std::span<const Sphere> spheres) {
    boxes_.reserve(spheres.size());
    centres_.reserve(spheres.size());
    for (const Sphere& s : spheres) {
      boxes_.push_back({s.position - glm::vec3(s.radius), s.position + glm::vec3(s.radius)});
      centres_.push_back(s.position);
    }
    for (const Box& b : boxes_) {
      const glm::vec3 m = glm::max(glm::abs(b.lo), glm::abs(b.hi));
      bvh_.maxCoordinate = std::max({bvh_.maxCoordinate, m.x, m.y, m.z});
    }
    for (const Sphere& s : spheres) bvh_.maxRadius = std::max(bvh_.maxRadius, s.radius);
    bvh_.order.resize(spheres.size());
    for (std::uint32_t i = 0; i < bvh_.order.size(); ++i) bvh_.order[i] = i;
    bvh_.nodes.reserve(2 * spheres.size());
  }

  Bvh build() && {
    bvh_.nodes.emplace_back();
    buildNode(0, 0, static_cast<std::uint32_t>(bvh_.order.size()), 0);
    return std::move(bvh_);
  }

 private:
  void buildNode(std::size_t node, std::uint32_t begin, std::uint32_t end, int depth) {
    Box bounds, centroids;
    for (std::uint32_t i = begin; i < end; ++i) {
      bounds.grow(boxes_[bvh_.order[i]]);
      centroids.grow(centres_[bvh_.order[i]]);
    }
    bvh_.nodes[node].lo = bounds.lo;
    bvh_.nodes[node].hi = bounds.hi;
    bvh_.depth = std::max(bvh_.depth, depth);
    const std::uint32_t count = end - begin;
    const Split split = count <= kBvhMaxLeafSize || depth >= kBvhMaxDepth ? Split{} : bestSplit(begin, end, centroids);
    const std::uint32_t middle = split.axis < 0 ? end : partition(begin, end, split, centroids);
    if (middle == begin || middle == end) {
      makeLeaf(node, begin, count);
      return;
    }
    const auto left = static_cast<std::uint32_t>(bvh_.nodes.size());
    bvh_.nodes.emplace_back();
    bvh_.nodes.emplace_back();
    bvh_.nodes[node].first = left;
    bvh_.nodes[node].meta = static_cast<std::uint32_t>(split.axis) << 30;
    buildNode(left, begin, middle, depth + 1);
    buildNode(left + 1, middle, end, depth + 1);
  }

  void makeLeaf(std::size_t node, std::uint32_t begin, std::uint32_t count) {
    if (count > BvhNode::kCountMask) throw std::length_error("BVH leaf too large");
    bvh_.nodes[node].first = begin;
    bvh_.nodes[node].meta = count;
  }

  [[nodiscard]] int binOf(const glm::vec3& c, int axis, const Box& centroids) const {
    const float extent = centroids.hi[axis] - centroids.lo[axis];
    const auto b = static_cast<int>(static_cast<float>(kBins) * (c[axis] - centroids.lo[axis]) / extent);
    return std::clamp(b, 0, kBins - 1);
  }

  // The binned SAH split of the range, or none (axis -1) when a leaf is cheaper.
  [[nodiscard]] Split bestSplit(std::uint32_t begin, std::uint32_t end, const Box& centroids) const {
    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(centroids.hi[axis] > centroids.lo[axis])) continue;
      std::array<Bin, kBins> bins{};
      for (std::uint32_t i = begin; i < end; ++i) {
        Bin& bin = bins[static_cast<std::size_t>(binOf(centres_[bvh_.order[i]], axis, centroids))];
        bin.bounds.grow(boxes_[bvh_.order[i]]);
        ++bin.count;
      }
      considerSplits(bins, axis, best);
    }
    // A leaf costs one test per sphere; an inner node one box test more.
    if (end - begin <= 2 * kBvhMaxLeafSize && best.cost >= static_cast<float>(end - begin)) return {};
    return best;
  }

  // SAH cost (in units of sphere tests, relative to the parent's area) of
  // each plane between bins, from prefix and suffix sweeps.
  static void considerSplits(const std::array<Bin, kBins>& bins, int axis, Split& best) {
    std::array<float, kBins> rightCost{};
    Box right;
    std::uint32_t rightCount = 0;
    for (int b = kBins - 1; b > 0; --b) {
      right.grow(bins[static_cast<std::size_t>(b)].bounds);
      rightCount += bins[static_cast<std::size_t>(b)].count;
      rightCost[static_cast<std::size_t>(b)] = right.halfArea() * static_cast<float>(rightCount);
    }
    Box left, all = right;
    all.grow(bins[0].bounds);
    std::uint32_t leftCount = 0;
    const float parentArea = std::max(all.halfArea(), std::numeric_limits<float>::min());
    for (int b = 0; b < kBins - 1; ++b) {
      left.grow(bins[static_cast<std::size_t>(b)].bounds);
      leftCount += bins[static_cast<std::size_t>(b)].count;
      if (leftCount == 0 || rightCost[static_cast<std::size_t>(b) + 1] == 0.0f) continue;
      const float cost =
          1.0f +
          (left.halfArea() * static_cast<float>(leftCount) + rightCost[static_cast<std::size_t>(b) + 1]) / parentArea;
      if (cost < best.cost) best = {axis, b, cost};
    }
  }

  std::uint32_t partition(std::uint32_t begin, std::uint32_t end, const Split& split, const Box& centroids) {
    const auto first = bvh_.order.begin() + begin;
    const auto mid = std::partition(first, bvh_.order.begin() + end, [&](std::uint32_t s) {
      return binOf(centres_[s], split.axis, centroids) <= split.bin;
    });
    return static_cast<std::uint32_t>(mid - bvh_.order.begin());
  }

  std::vector<Box> boxes_;
  std::vector<glm::vec3> centres_;
  Bvh bvh_;
};

}  // namespace reference_bvh

// rt::buildBvh's tree as the one-thread builder made it (buildMs left 0).
inline Bvh referenceBvh(std::span<const Sphere> spheres) {
  if (spheres.empty()) throw std::invalid_argument("a BVH needs at least one sphere");
  return reference_bvh::Builder(spheres).build();
}

}  // namespace rt::test
