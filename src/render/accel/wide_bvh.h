#pragma once
// The wide BVH that single rays walk (--traversal single and hybrid): the
// binary SAH tree of bvh.h collapsed so that a node holds up to
// kWideBvhWidth children, their boxes as structure of arrays, so that one
// ray is tested against all of a node's boxes in one vector pass. Subtrees
// of at most kWideBvhWidth spheres become leaves, their spheres in a block
// of their own, so that a leaf is tested in one vector pass too (a pile of
// more coincident spheres than that becomes a node of such leaves). Built from
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

// A child slot: a wide node's index, or a leaf (top bit set): the leaf's
// LeafBlock index in the low 28 bits and its sphere count less one in the
// next 3 (a leaf holds 1 to kWideBvhWidth spheres, one block).
struct WideChild {
  static constexpr std::uint32_t kLeafBit = 0x80000000u;
  static constexpr std::uint32_t kBlockMask = 0x0fffffffu;
  std::uint32_t bits;  // no initializer: traversal stacks of these are not zeroed per ray

  [[nodiscard]] bool leaf() const { return (bits & kLeafBit) != 0; }
  [[nodiscard]] std::uint32_t node() const { return bits; }
  [[nodiscard]] std::uint32_t block() const { return bits & kBlockMask; }
  [[nodiscard]] std::uint32_t count() const { return ((bits >> 28) & 7u) + 1u; }
  static WideChild inner(std::uint32_t node) { return {node}; }
  static WideChild leafOf(std::uint32_t block, std::uint32_t count) {
    return {kLeafBit | ((count - 1u) << 28) | block};
  }
};

// 256 bytes, four cache lines: a node's boxes and its children.
struct alignas(64) WideBvhNode {
  static constexpr int kWidth = kWideBvhWidth;
  // The children's boxes by plane: lo x, y, z, then hi x, y, z. Empty slots
  // hold an empty box (lo +inf, hi -inf), which no ray enters.
  enum Plane { kLoX, kLoY, kLoZ, kHiX, kHiY, kHiZ };
  std::array<std::array<float, kWidth>, 6> bounds;
  std::array<WideChild, kWidth> child;
  std::uint32_t childCount = 0;  // slots 0 .. childCount-1 are used
};
static_assert(kWideBvhWidth != 8 || sizeof(WideBvhNode) == 256);

// A leaf's spheres as the kernels test them, two cache lines: centre and
// float radius squared per slot. Unused slots have radius squared -1, which
// no ray hits.
struct alignas(64) LeafBlock {
  std::array<float, kWideBvhWidth> centerX, centerY, centerZ, radiusSquared;
};
static_assert(kWideBvhWidth != 8 || sizeof(LeafBlock) == 128);

struct WideBvh {
  std::vector<WideBvhNode> nodes;  // nodes[0] is the root (always an inner node)
  std::vector<LeafBlock> leaves;
  // The scene index of each leaf slot (kWideBvhWidth per block; -1 unused),
  // apart from the blocks: read only for the spheres a ray hits.
  std::vector<std::int32_t> index;
  int depth = 0;  // levels below the root, for sizing traversal stacks
  double buildMs = 0.0;
};

// Collapses `bvh` (built over `spheres`) into a wide BVH. Deterministic.
WideBvh buildWideBvh(const Bvh& bvh, std::span<const Sphere> spheres);

}  // namespace rt
