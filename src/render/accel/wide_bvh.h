#pragma once
// The wide BVH that single rays walk (--traversal single and hybrid): the
// binary SAH tree of bvh.h collapsed so that a node holds up to
// kWideBvhWidth children, their boxes as structure of arrays, so that one
// ray is tested against all of a node's boxes in one vector pass. Subtrees
// of at most kWideBvhWidth spheres become leaves, their spheres in arrays
// of their own, so that a leaf is tested in one vector pass too. Built from
// the binary tree, it holds the same spheres under the same boxes: it
// changes which boxes a ray visits, never which sphere it hits nearest.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "render/accel/bvh.h"
#include "scene/scene.h"

namespace rt {

// Children per node: 8 floats fill an AVX2 vector (and half an AVX-512 one).
inline constexpr int kWideBvhWidth = 8;

struct alignas(32) WideBvhNode {
  static constexpr int kWidth = kWideBvhWidth;
  // The children's boxes by plane: lo x, y, z, then hi x, y, z. Empty slots
  // hold an empty box (lo +inf, hi -inf), which no ray enters.
  enum Plane { kLoX, kLoY, kLoZ, kHiX, kHiY, kHiZ };
  std::array<std::array<float, kWidth>, 6> bounds;
  // Per slot: an inner child's node index, or a leaf's first slot in the
  // WideBvh's sphere arrays.
  std::array<std::uint32_t, kWidth> child;
  // Per slot: 0 for an inner child, a leaf's sphere count otherwise.
  std::array<std::uint32_t, kWidth> leafCount;
  std::uint32_t childCount = 0;  // slots 0 .. childCount-1 are used
};

struct WideBvh {
  std::vector<WideBvhNode> nodes;  // nodes[0] is the root (always an inner node)
  // The spheres leaf by leaf, as the kernels test them: centre, float
  // radius squared, index in the scene. Followed by kWideBvhWidth slots of
  // padding, so that a vector load at any leaf stays inside the arrays.
  std::vector<float> centerX, centerY, centerZ, radiusSquared;
  std::vector<std::int32_t> index;
  int depth = 0;  // levels below the root, for sizing traversal stacks
  double buildMs = 0.0;
};

// Collapses `bvh` (built over `spheres`) into a wide BVH. Deterministic.
WideBvh buildWideBvh(const Bvh& bvh, std::span<const Sphere> spheres);

}  // namespace rt
