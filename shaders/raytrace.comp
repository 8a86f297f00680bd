#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#if RT_PRECISION_F16
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require
#endif
// The GPU renderer: the render model (render_model.glsl, nearest_hit.glsl)
// traced as one megakernel (docs/render-model.md section 3, "How the GPU
// renderer walks the BVH"): one invocation per pixel follows its path
// through every bounce. The subgroup extensions serve --counters only
// (nearest_hit.glsl). Built twice: RT_PRECISION_F16 1 computes the model
// in half precision (--precision f16, render_model.glsl).

#include "bvh_layout.h"
#include "gpu_interface.h"
#include "model_constants.h"

layout(local_size_x = RT_WORKGROUP_SIZE_X, local_size_y = RT_WORKGROUP_SIZE_Y) in;

// Variant selection (the C++ kernel's template parameters) ===================
layout(constant_id = RT_SPEC_TWO_PASS) const bool TWO_PASS = false;
layout(constant_id = RT_SPEC_BOUNCE_EXIT) const bool BOUNCE_EXIT = true;
// The scene's render.maxDepth: a specialization constant rather than a push
// constant because it sizes the two-pass algorithm's stored arrays.
layout(constant_id = RT_SPEC_MAX_DEPTH) const int MAX_DEPTH = 5;
// --accel bvh: walk the hierarchy instead of testing every sphere. Off, the
// traversal is compiled out and brute force runs exactly as without it.
layout(constant_id = RT_SPEC_USE_BVH) const bool USE_BVH = false;
// The binary walk's stack size, from the tree's depth (nearestHitInBvh()).
layout(constant_id = RT_SPEC_BVH_STACK_SIZE) const int BVH_STACK_SIZE = RT_BVH_MAX_DEPTH + 2;
// rt::Bvh::pad, the model of the traversal pad (rt::TraversalPadModel).
layout(constant_id = RT_SPEC_BVH_PAD_RADIUS) const float BVH_PAD_RADIUS = 0.0;
layout(constant_id = RT_SPEC_BVH_PAD_COORDINATE) const float BVH_PAD_COORDINATE = 0.0;
layout(constant_id = RT_SPEC_BVH_PAD_ORIGIN_SLOPE) const float BVH_PAD_ORIGIN_SLOPE = 0.0;


// --gpu-bvh wide: walk rt::WideBvh instead of the binary tree; its stack
// size, from the tree's depth (nearestHitInWideBvh()).
layout(constant_id = RT_SPEC_WIDE_BVH) const bool WIDE_BVH = false;
layout(constant_id = RT_SPEC_WIDE_STACK_SIZE) const int WIDE_STACK_SIZE = 1;
// --gpu-bvh grid: rt::SphereGrid's corner, cell side (a power of two) and
// cells per axis.
layout(constant_id = RT_SPEC_GRID) const bool GRID = false;
layout(constant_id = RT_SPEC_GRID_ORIGIN_X) const float GRID_ORIGIN_X = 0.0;
layout(constant_id = RT_SPEC_GRID_ORIGIN_Y) const float GRID_ORIGIN_Y = 0.0;
layout(constant_id = RT_SPEC_GRID_ORIGIN_Z) const float GRID_ORIGIN_Z = 0.0;
layout(constant_id = RT_SPEC_GRID_CELL_SIZE) const float GRID_CELL_SIZE = 1.0;
layout(constant_id = RT_SPEC_GRID_CELLS_X) const int GRID_CELLS_X = 1;
layout(constant_id = RT_SPEC_GRID_CELLS_Y) const int GRID_CELLS_Y = 1;
layout(constant_id = RT_SPEC_GRID_CELLS_Z) const int GRID_CELLS_Z = 1;
// The spheres it keeps apart: leaf slots 0 .. GRID_APART_COUNT - 1, tested
// by every ray before the walk.
layout(constant_id = RT_SPEC_GRID_APART_COUNT) const int GRID_APART_COUNT = 0;
// --counters: tally rays, visits, tests and lane slots (nearest_hit.glsl).
layout(constant_id = RT_SPEC_COUNTERS) const bool COUNTERS = false;
// Lavapipe: find out whether its loop limit cut a loop short (loop_guard.glsl).
layout(constant_id = RT_SPEC_LOOP_GUARD) const bool LOOP_GUARD = false;

// Inputs =====================================================================
#include "frame_inputs.glsl"

// --accel bvh, --gpu-bvh binary: rt::gpu::GpuBinaryNode (gpu_layout.h),
// 64 bytes per inner node of rt::Bvh holding its two children's boxes, as
// four uvec4s: {child 0's lo, its word}, {child 0's hi, its leaf sphere
// count (0: inner)}, and the same for child 1. uints, not floats, so that
// the words and counts (denormals as floats) come through untouched; the
// bounds are reinterpreted as floats.
// Slots a variant does not use name the sphere buffer and are never read.
layout(std430, set = 0, binding = RT_BINDING_BVH_NODES) readonly buffer BvhNodes {
  uvec4 bvhNodes[];
};
layout(std430, set = 0, binding = RT_BINDING_BVH_ORDER) readonly buffer BvhOrder {
  uint bvhOrder[];  // sphere indices, leaf by leaf
};
// The spheres of the BVH's leaves (position, radius) in leaf order: the
// binary tree's order, or the wide tree's leaf slots; a leaf's spheres are
// read without going through their indices, which are read only for a hit.
layout(std430, set = 0, binding = RT_BINDING_LEAF_SPHERES) readonly buffer LeafSpheres {
  vec4 leafSpheres[];
};

// The wide BVH's nodes (16 uvec4s each, nearest_hit.glsl) and the scene
// index of each leaf slot.
layout(std430, set = 0, binding = RT_BINDING_WIDE_NODES) readonly buffer WideNodes {
  uvec4 wideNodes[];
};
layout(std430, set = 0, binding = RT_BINDING_WIDE_INDEX) readonly buffer WideIndex {
  int wideIndex[];
};

// --gpu-bvh grid: each cell's first slot and sphere count (rt::SphereGrid;
// its slots' spheres and scene indices are leafSpheres and bvhOrder).
layout(std430, set = 0, binding = RT_BINDING_GRID_CELLS) readonly buffer GridCells {
  uvec2 gridCells[];
};

layout(std430, set = 0, binding = RT_BINDING_COUNTERS) buffer Counters {
  uint counterWords[];  // RT_COUNTER_COPIES x RT_COUNTER_SLOTS x (low, high)
};

layout(std430, set = 0, binding = RT_BINDING_LOOP_GUARD) buffer LoopGuard {
  uint loopGuardWords[];  // [0]: raised to 1 where the limit was reached; [1]: always 0
};

#include "render_model.glsl"
#include "loop_guard.glsl"
#include "nearest_hit.glsl"

#include "path_tracing.glsl"

// The image's overhang to whole workgroups has invocations but no pixels.
bool insideImage(ivec2 pixel) { return pixel.x < pc.width && pixel.y < pc.height; }

void renderPixel(ivec2 pixel) {
  Ray ray = primaryRay(pixel.x, pixel.y);
  real3 color = TWO_PASS ? traceTwoPass(ray) : traceSinglePass(ray);
  imageStore(outputImage, pixel, toRgba8(color));
}

// One invocation per pixel, in 8x8 workgroups; the grid is rounded up to
// whole workgroups.
void main() {
  beginCounting();
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (insideImage(pixel)) renderPixel(pixel);
  flushCounters();
  reportLoopLimit();
}
