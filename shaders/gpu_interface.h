// The interface between the GPU renderer (src/gpu/compute/gpu_renderer.cpp)
// and shaders/raytrace.comp: binding slots, specialization constant ids, the
// workgroup size and the push-constant block's members. Included by C++ and
// GLSL, so it holds #defines only. The C++ mirrors of the data layouts
// (GPUSphere, the push constants) are in src/gpu/compute/gpu_layout.h, where
// static_asserts pin every offset.
#ifndef RT_GPU_INTERFACE_H
#define RT_GPU_INTERFACE_H

// Descriptor set 0.
#define RT_BINDING_SPHERES 0
#define RT_BINDING_OUTPUT 1
// The BVH of --accel bvh (rt::Bvh::nodes and rt::Bvh::order).
#define RT_BINDING_BVH_NODES 2
#define RT_BINDING_BVH_ORDER 3
// The wide BVH of --gpu-bvh wide (rt::WideBvh::nodes and rt::WideBvh::index).
#define RT_BINDING_WIDE_NODES 4
#define RT_BINDING_WIDE_INDEX 5
// --counters: RT_COUNTER_COPIES copies of RT_COUNTER_SLOTS 64-bit counters.
#define RT_BINDING_COUNTERS 6
// --accel bvh: the leaves' spheres in leaf order (of the BVH walked).
#define RT_BINDING_LEAF_SPHERES 7
// The ray-tracing pipeline renderer (gpu_rt): the top-level acceleration
// structure its ray-generation shader traces (with the spheres and the
// output image at their slots above; it binds nothing else).
#define RT_BINDING_TLAS 8
// --gpu-bvh grid: each cell's first slot and sphere count (rt::SphereGrid;
// the slots' spheres and indices take the leaf spheres' and the BVH
// order's bindings).
#define RT_BINDING_GRID_CELLS 9
// Lavapipe only: the words of its loop guard (loop_guard.glsl).
#define RT_BINDING_LOOP_GUARD 10

// Specialization constants: fixed per pipeline, so the compiler removes the
// branches of the variants that are not used (as the C++ templates do).
#define RT_SPEC_TWO_PASS 0
#define RT_SPEC_BOUNCE_EXIT 1
#define RT_SPEC_MAX_DEPTH 2
// --accel bvh, and the traversal pad's model (rt::Bvh::pad: radius,
// coordinate and origin slope): fixed per scene, and the push constants
// have no room left for them.
#define RT_SPEC_USE_BVH 3
#define RT_SPEC_BVH_PAD_RADIUS 4
#define RT_SPEC_BVH_PAD_COORDINATE 5
// --gpu-bvh wide, and the traversal stack it needs for the tree's depth.
#define RT_SPEC_WIDE_BVH 6
#define RT_SPEC_WIDE_STACK_SIZE 7
// --counters.
#define RT_SPEC_COUNTERS 8
// The binary walk's stack, from the tree's depth.
#define RT_SPEC_BVH_STACK_SIZE 9
// --gpu-bvh grid, and the grid's corner, cell side and cells per axis.
#define RT_SPEC_GRID 10
#define RT_SPEC_GRID_ORIGIN_X 11
#define RT_SPEC_GRID_ORIGIN_Y 12
#define RT_SPEC_GRID_ORIGIN_Z 13
#define RT_SPEC_GRID_CELL_SIZE 14
#define RT_SPEC_GRID_CELLS_X 15
#define RT_SPEC_GRID_CELLS_Y 16
#define RT_SPEC_GRID_CELLS_Z 17
#define RT_SPEC_BVH_PAD_ORIGIN_SLOPE 18
// Lavapipe's loop limit (loop_guard.glsl).
#define RT_SPEC_LOOP_GUARD 19
// --gpu-bvh grid: the spheres kept apart, the first slots (rt::SphereGrid::apartCount).
#define RT_SPEC_GRID_APART_COUNT 20

// One invocation per pixel in 8x8 tiles: two 32-wide warps on NVIDIA, one
// 64-wide wave on AMD, eight 8-wide rows for lavapipe's 256-bit vectors.
#define RT_WORKGROUP_SIZE_X 8
#define RT_WORKGROUP_SIZE_Y 8

// --counters: slots 0 .. 63 count rays by bounce depth, then the LaneCounters
// fields below, each a 64-bit counter as two uints (low word first). The
// shader spreads its atomics over RT_COUNTER_COPIES copies of the slots
// (by workgroup), which the renderer sums.
#define RT_COUNTER_NODE_VISITS 64
#define RT_COUNTER_NODE_LANE_SLOTS 65
#define RT_COUNTER_SPHERE_TESTS 66
#define RT_COUNTER_SPHERE_LANE_SLOTS 67
#define RT_COUNTER_SHADE_LANE_SLOTS 68
#define RT_COUNTER_SHADE_LANES_ACTIVE 69
#define RT_COUNTER_SLOTS 70
#define RT_COUNTER_COPIES 64

// Lavapipe's compiler (gallivm) ends a subgroup's loops once they have run
// this many iterations in all (loop_guard.glsl).
#define RT_LAVAPIPE_LOOP_ITERATIONS 65535

// The most the push-constant block may take (bytes): the Vulkan-guaranteed
// minimum of maxPushConstantsSize, so the pipeline runs on every device.
#define RT_PUSH_CONSTANT_BYTES 128

// The push-constant block, one MEMBER(GLSL type, name, byte offset) per
// member: raytrace.comp declares the block from this list and
// src/gpu/compute/gpu_layout.h the C++ mirror (rt::gpu::FrameConstants), so the two
// cannot differ in a name, a type or an order. The shader places each
// member at the listed offset and the C++ side asserts that it lies there
// in the C++ struct too, so a wrong offset fails the build (glslang also
// rejects a misaligned one). The camera and image size change per frame,
// the rest (rt::ShadingParams less maxDepth, a specialization constant)
// per scene. Each vec3 but the last shares its 16-byte slot with a scalar.
#define RT_FRAME_CONSTANTS(MEMBER)     \
  MEMBER(vec3, cameraPosition, 0)      \
  MEMBER(float, tanHalfFov, 12)        \
  MEMBER(vec3, cameraForward, 16)      \
  MEMBER(int, width, 28)               \
  MEMBER(vec3, cameraRight, 32)        \
  MEMBER(int, height, 44)              \
  MEMBER(vec3, cameraUp, 48)           \
  MEMBER(uint, sphereCount, 60)        \
  MEMBER(vec3, toLight, 64)            \
  MEMBER(float, reflectivity, 76)      \
  MEMBER(vec3, lightColor, 80)         \
  MEMBER(float, shininess, 92)         \
  MEMBER(vec3, ambientColor, 96)       \
  MEMBER(float, specularStrength, 108) \
  MEMBER(vec3, background, 112)

#endif
