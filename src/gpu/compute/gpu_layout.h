#pragma once
// C++ mirrors of the data shaders/raytrace.comp reads, byte for byte. The
// static_asserts pin every offset the shader declares, so a change on one
// side that is not made on the other fails to compile.
#include <cstddef>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <span>
#include <vector>

#include "gpu_interface.h"
#include "render/accel/bvh.h"
#include "render/accel/sphere_grid.h"
#include "render/accel/wide_bvh.h"
#include "render/shading_params.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt::gpu {

// One sphere in the storage buffer (std430: a vec3 is 16-byte aligned, the
// float after it fills the vec3's last 4 bytes; the struct is padded to 32).
// The shader declares the same bytes as two vec4s (positionRadius,
// colorPad), so the intersection loop loads a sphere in one 16-byte read.
struct GPUSphere {
  glm::vec3 position;
  float radius;
  glm::vec3 color;
  float pad = 0.0f;
};
static_assert(sizeof(GPUSphere) == 32);
static_assert(offsetof(GPUSphere, position) == 0);
static_assert(offsetof(GPUSphere, radius) == 12);
static_assert(offsetof(GPUSphere, color) == 16);
static_assert(offsetof(GPUSphere, pad) == 28);

// --gpu-bvh binary: each inner node of rt::Bvh as the shader walks it, with
// its two children's boxes (Aila and Laine's layout: a visit tests both and
// goes on without a stack round trip). A child's word is its node's
// number in this array (below), or for a leaf its first slot in Bvh::order
// with its sphere count beside the box (0 for an inner child). Bvh's
// encoding and depth limit are shaders/bvh_layout.h's, which both sides
// include.
struct GpuBinaryNode {
  glm::vec3 lo0;
  std::uint32_t child0;
  glm::vec3 hi0;
  std::uint32_t count0;
  glm::vec3 lo1;
  std::uint32_t child1;
  glm::vec3 hi1;
  std::uint32_t count1;
};
static_assert(sizeof(GpuBinaryNode) == 64);
static_assert(offsetof(GpuBinaryNode, child0) == 12 && offsetof(GpuBinaryNode, count0) == 28);
static_assert(offsetof(GpuBinaryNode, child1) == 44 && offsetof(GpuBinaryNode, count1) == 60);
static_assert(sizeof(decltype(Bvh::order)::value_type) == sizeof(std::uint32_t));

// The nodes the shader walks: the inner nodes of bvh.nodes only, numbered
// depth first (a node, then its left subtree, then its right one), so that
// no leaf leaves a hole in the buffer and a node's left child is its
// neighbour in memory. Numbered as in bvh.nodes, half the entries (the
// leaves) were holes: twice the device memory, and 0.7 % slower at
// 1,000,000 spheres on the H100 (docs/experiments/gpu-traversal.md). A tree
// that is one leaf gets a root with that leaf as both children: testing its
// spheres twice cannot change the nearest hit. Each child's box is widened
// by `boxPad` on every side: the pad every ray of the scene needs beyond
// what the boxes carry (sceneTraversalPad of the tree's pad model: the whole
// scene pad, or with local padding only the rays' share), so that the
// shader's box test does not widen it ray by ray (docs/render-model.md
// section 3, "The traversal pad").
std::vector<GpuBinaryNode> toGpuBinaryNodes(const Bvh& bvh, float boxPad);

// The leaves' spheres as (position, radius) in leaf order: `order[k]`'s
// sphere in slot k; a negative index (an unused wide leaf slot) gives zeros.
template <typename Index>
std::vector<glm::vec4> leafSpheres(std::span<const Sphere> spheres, std::span<const Index> order) {
  std::vector<glm::vec4> out(order.size(), glm::vec4(0.0f));
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (order[k] < 0) continue;
    const Sphere& s = spheres[static_cast<std::size_t>(order[k])];
    out[k] = glm::vec4(s.position, s.radius);
  }
  return out;
}

// --gpu-bvh wide: rt::WideBvh's nodes go to the shader as built, 16 vec4s
// each (shaders/nearest_hit.glsl): the six planes of 8 floats, the child
// words, the child count. Its index array is plain ints.
static_assert(kWideBvhWidth == 8, "the shader walks 8-wide nodes");
static_assert(sizeof(WideBvhNode) == 256);
static_assert(offsetof(WideBvhNode, bounds) == 0);
static_assert(offsetof(WideBvhNode, child) == 12 * 16);
static_assert(offsetof(WideBvhNode, childCount) == 14 * 16);
static_assert(sizeof(WideChild) == sizeof(std::uint32_t));
static_assert(sizeof(decltype(WideBvh::index)::value_type) == sizeof(std::int32_t));

// The push-constant block, declared from the member list the shader
// declares its block from (RT_FRAME_CONSTANTS, shaders/gpu_interface.h):
// the GLSL type names stand for their C++ twins here.
using vec3 = glm::vec3;
using uint = std::uint32_t;
static_assert(sizeof(int) == 4 && sizeof(float) == 4, "GLSL's int and float are 32 bits");

#define RT_CPP_MEMBER(type, name, at) type name;
struct FrameConstants {
  RT_FRAME_CONSTANTS(RT_CPP_MEMBER)
};
#undef RT_CPP_MEMBER
static_assert(sizeof(FrameConstants) <= RT_PUSH_CONSTANT_BYTES);
// Each member where the list (and so the shader) puts it.
#define RT_CPP_OFFSET(type, name, at) static_assert(offsetof(FrameConstants, name) == (at), #name);
RT_FRAME_CONSTANTS(RT_CPP_OFFSET)
#undef RT_CPP_OFFSET

// The specialization constants of one pipeline variant.
struct SpecializationConstants {
  std::uint32_t twoPass;     // VkBool32
  std::uint32_t bounceExit;  // VkBool32
  std::int32_t maxDepth;
  std::uint32_t useBvh = 0;                          // VkBool32: --accel bvh
  float bvhPadRadius = 0.0f;                         // Bvh::pad, the traversal pad's model;
  float bvhPadCoordinate = 0.0f;                     // unused without the BVH
  std::uint32_t wideBvh = 0;                         // VkBool32: --gpu-bvh wide
  std::int32_t wideStackSize = 1;                    // entries the wide walk's stack needs
  std::uint32_t counters = 0;                        // VkBool32: --counters
  std::int32_t bvhStackSize = RT_BVH_MAX_DEPTH + 2;  // entries the binary walk's stack needs
  std::uint32_t grid = 0;                            // VkBool32: --gpu-bvh grid
  float gridOrigin[3] = {0.0f, 0.0f, 0.0f};          // rt::SphereGrid's origin, cellSize and cells
  float gridCellSize = 1.0f;
  std::int32_t gridCells[3] = {1, 1, 1};
  float bvhPadOriginSlope = 0.0f;   // Bvh::pad.originSlope
  std::uint32_t loopGuard = 0;      // VkBool32: lavapipe (shaders/loop_guard.glsl)
  std::int32_t gridApartCount = 0;  // rt::SphereGrid::apartCount
};

// The binary walk pushes at most one child per level of the tree on its way
// down (shaders/nearest_hit.glsl).
constexpr std::int32_t binaryStackSize(const Bvh& bvh) { return bvh.depth + 2; }

// The wide walk pushes at most kWideBvhWidth - 1 children per level of the
// tree on its way down (shaders/nearest_hit.glsl).
constexpr std::int32_t wideStackSize(const WideBvh& wide) { return (kWideBvhWidth - 1) * (wide.depth + 1) + 1; }

// --gpu-bvh grid: a cell as the shader reads it, its first slot and its
// sphere count.
std::vector<glm::uvec2> toGpuGridCells(const SphereGrid& grid);

std::vector<GPUSphere> toGpuSpheres(std::span<const Sphere> spheres);

// Frame constants of one frame: the scene's shading parameters (built once
// per scene) and sphere count, the frame's camera and the image size.
FrameConstants makeFrameConstants(const ShadingParams& shading, std::uint32_t sphereCount, const CameraFrame& camera,
                                  Extent extent);

}  // namespace rt::gpu
