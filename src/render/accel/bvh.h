#pragma once
// A bounding-volume hierarchy over a scene's spheres, built once per scene
// in prepare() with a binned surface-area heuristic. Binary, 32-byte nodes
// in one array, children side by side: compact enough for a storage buffer
// and cheap to walk with a small fixed stack, one ray or one packet at a
// time.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <vector>

#include "bvh_layout.h"
#include "render/accel/accel_structure_info.h"
#include "render/render_options.h"
#include "scene/scene.h"

namespace rt {

struct BvhNode {
  glm::vec3 lo;         // bounds of every sphere below
  std::uint32_t first;  // leaf: first slot in Bvh::order; inner: index of the left child (right = left + 1)
  glm::vec3 hi;
  std::uint32_t meta;  // leaf: sphere count (> 0); inner: 0 in the low 30 bits, split axis in the top 2

  [[nodiscard]] bool leaf() const { return (meta & kCountMask) != 0; }
  [[nodiscard]] std::uint32_t count() const { return meta & kCountMask; }
  [[nodiscard]] int axis() const { return static_cast<int>(meta >> 30); }

  static constexpr std::uint32_t kCountMask = RT_BVH_COUNT_MASK;
};
static_assert(sizeof(BvhNode) == 32);

// How the walks widen a tree's boxes so that no sphere the float test hits
// is culled (docs/render-model.md section 3, "The traversal pad"). Every
// walk computes, once per ray, traversalPad(model, |origin|) and widens each
// box by it, in space and along the ray; what the boxes carry is the
// build's choice (BoxPadding, from the schema):
// - scene: boxes as tight as the spheres, the pad sized by the scene's
//   largest radius and |coordinate| (radius, coordinate; originSlope 0);
// - local: each box already widened by twice the part of the pad that its
//   own spheres' radii and coordinates give, so the ray's part is linear in
//   its origin (radius and coordinate 0, originSlope > 0).
struct TraversalPadModel {
  float radius = 0.0f;
  float coordinate = 0.0f;
  float originSlope = 0.0f;
};

struct Bvh {
  std::vector<BvhNode> nodes;        // nodes[0] is the root
  std::vector<std::uint32_t> order;  // sphere indices, leaf by leaf
  int depth = 0;                     // levels below the root, for sizing traversal stacks
  float maxRadius = 0.0f;            // of any sphere, and the largest |coordinate| of
  float maxCoordinate = 0.0f;        // any sphere's bounds (sceneTraversalPad's)
  BoxPadding padding = BoxPadding::scene;
  TraversalPadModel pad;  // what the walks' traversalPad() reads
  double price = 0.0;     // padPrice() of the padding chosen: a ray's estimated visits and tests
  double buildMs = 0.0;   // wall time of buildBvh()
};

// How far a box must be widened, in space and along the ray, so that no
// sphere whose float intersection (docs/render-model.md section 3) reports a
// hit is culled by its box: the float test may report a hit a little
// outside the exact sphere, most near tangency, and its distance may be off
// by as much. Grows with the ray origin's largest |coordinate|, and with
// the largest radius and |coordinate| of the spheres the box holds.
inline float traversalPad(float maxRadius, float maxCoordinate, float originMaxCoordinate) {
  const float scale = originMaxCoordinate + maxCoordinate;
  return float(RT_BVH_PAD_SCALE) * scale + float(RT_BVH_PAD_TANGENT) * std::sqrt(maxRadius * scale) +
         float(RT_BVH_PAD_RADIUS) * maxRadius + float(RT_BVH_PAD_MIN);
}

// The pad of a ray from `originMaxCoordinate` in a tree padded as `model`
// says: the scene's pad for BoxPadding::scene, the ray's part for local
// (whose zero radius and coordinate leave the first formula at
// PAD_SCALE |origin| + PAD_MIN, to which the origin's share of the tangency
// term is added).
inline float traversalPad(const TraversalPadModel& model, float originMaxCoordinate) {
  return traversalPad(model.radius, model.coordinate, originMaxCoordinate) + model.originSlope * originMaxCoordinate;
}

inline float traversalPad(const Bvh& bvh, float originMaxCoordinate) {
  return traversalPad(bvh.pad, originMaxCoordinate);
}

// The pad of every ray a scene traces, at least traversalPad of any of its
// origins: reflected rays start on the spheres' surfaces (within
// maxCoordinate), camera rays at the camera (within `cameraBound`,
// scene/camera.h). A float hit point or camera position may lie an ulp past
// those bounds, so the bound is raised by 2^-20 of itself before it sizes
// the pad.
inline float originBound(float maxCoordinate, float cameraBound) {
  const float bound = std::max(maxCoordinate, cameraBound);
  return bound + bound * 0x1p-20f;
}

inline float sceneTraversalPad(float maxRadius, float maxCoordinate, float cameraBound) {
  return traversalPad(maxRadius, maxCoordinate, originBound(maxCoordinate, cameraBound));
}

// The pad of every ray of the scene in `bvh`'s model: with local padding,
// only the rays' part (the boxes carry the rest).
inline float sceneTraversalPad(const Bvh& bvh, float cameraBound) {
  return traversalPad(bvh.pad, originBound(bvh.maxCoordinate, cameraBound));
}

// Deepest tree a traversal stack must hold (the build stops splitting there).
inline constexpr int kBvhMaxDepth = RT_BVH_MAX_DEPTH;
// When the build stops splitting: a range of at most `always` spheres is a
// leaf; one of up to `sahUpTo` stays a leaf where the SAH finds no cheaper
// split; any other is split, unless its spheres cannot be told apart
// (coincident centres), which stay together.
struct BvhLeafRule {
  std::uint32_t always;
  std::uint32_t sahUpTo;
};
// The CPU kernels' leaves: up to four spheres, eight where the SAH says so.
inline constexpr std::uint32_t kBvhMaxLeafSize = 4;
inline constexpr BvhLeafRule kBvhLeaves{kBvhMaxLeafSize, 2 * kBvhMaxLeafSize};
// One sphere per leaf: the GPU renderer's binary walk, which tests a leaf
// child's spheres in the visit that reaches it (docs/render-model.md
// section 3, "How the GPU renderer walks the BVH").
inline constexpr BvhLeafRule kSingleSphereLeaves{1, 1};

// Builds the hierarchy over `spheres` (at least one; finite, radii > 0, as
// the loader checks) on oneTBB, in the calling thread's task arena, with
// leaves as `leaves` says (always >= 1, sahUpTo >= always).
// Deterministic: the same spheres give the same tree, bit for bit, with any
// number of threads (tests/render/accel/bvh_build_test.cpp).
// `padding`: the boxes' padding, or none to let the build choose the one
// with the lower estimated cost (padPrice() below).
Bvh buildBvh(std::span<const Sphere> spheres, BvhLeafRule leaves = kBvhLeaves,
             std::optional<BoxPadding> padding = std::nullopt);

// The estimated cost of a ray's walk through `bvh` under `padding`, in
// sphere tests (a node visit counts as one): the surface-area heuristic of
// its boxes as that padding widens them, for a ray from the spheres' median
// |coordinate|, each box's chance taken against the region where most
// sphere centres lie (not the root's box, which one huge sphere can make
// far larger than where the rays go). Brute force costs the sphere count.
double padPrice(const Bvh& bvh, std::span<const Sphere> spheres, BoxPadding padding);

}  // namespace rt

namespace rt {

// --accel auto keeps the BVH where a ray's estimated tests through it
// (Bvh::price) are under this share of the sphere count, brute force's.
inline constexpr double kAutoBvhShare = 0.5;

// What a kernel holds for the --accel option: nothing for brute force, the
// BVH for bvh, rebuilt by every prepare(); for auto, the BVH where its price
// says it pays.
class AccelStructure {
 public:
  // Returns what runs: none or bvh (auto resolved).
  Accel prepare(std::span<const Sphere> spheres, Accel accel, BvhLeafRule leaves = kBvhLeaves) {
    bvh_.reset();
    if (accel == Accel::none) return Accel::none;
    bvh_ = buildBvh(spheres, leaves);
    if (accel == Accel::auto_ && !(bvh_->price < kAutoBvhShare * static_cast<double>(spheres.size()))) bvh_.reset();
    return bvh_ ? Accel::bvh : Accel::none;
  }
  // Null for brute force.
  [[nodiscard]] const Bvh* bvh() const { return bvh_ ? &*bvh_ : nullptr; }
  [[nodiscard]] std::optional<AccelStructureInfo> info() const {
    if (!bvh_) return std::nullopt;
    return AccelStructureInfo{Accel::bvh,   bvh_->buildMs, bvh_->nodes.size(), bvh_->depth,
                              std::nullopt, bvh_->padding, bvh_->price,        std::nullopt};
  }

 private:
  std::optional<Bvh> bvh_;
};

}  // namespace rt
