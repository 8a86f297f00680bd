// The interface between the GPU renderer (src/gpu/compute/gpu_renderer.cpp)
// and shaders/raytrace.comp: binding slots, specialization constant ids and
// the workgroup size. Included by C++ and GLSL, so it holds #defines only.
// The data layouts themselves (GPUSphere, push constants) are mirrored in
// src/gpu/compute/gpu_layout.h, where static_asserts pin every offset.
#ifndef RT_GPU_INTERFACE_H
#define RT_GPU_INTERFACE_H

// Descriptor set 0.
#define RT_BINDING_SPHERES 0
#define RT_BINDING_OUTPUT 1
// The BVH of --accel bvh (rt::Bvh::nodes and rt::Bvh::order).
#define RT_BINDING_BVH_NODES 2
#define RT_BINDING_BVH_ORDER 3

// Specialization constants: fixed per pipeline, so the compiler removes the
// branches of the variants that are not used (as the C++ templates do).
#define RT_SPEC_TWO_PASS 0
#define RT_SPEC_BOUNCE_EXIT 1
#define RT_SPEC_MAX_DEPTH 2
// --accel bvh, and the two scene bounds the traversal pad grows with
// (rt::Bvh::maxRadius, maxCoordinate): fixed per scene, and the push
// constants have no room left for them.
#define RT_SPEC_USE_BVH 3
#define RT_SPEC_BVH_MAX_RADIUS 4
#define RT_SPEC_BVH_MAX_COORDINATE 5

// One invocation per pixel in 8x8 tiles: two 32-wide warps on NVIDIA, one
// 64-wide wave on AMD, eight 8-wide rows for lavapipe's 256-bit vectors.
#define RT_WORKGROUP_SIZE_X 8
#define RT_WORKGROUP_SIZE_Y 8

// Size of the push-constant block (bytes): the Vulkan-guaranteed minimum
// of maxPushConstantsSize, so the pipeline runs on every device.
#define RT_PUSH_CONSTANT_BYTES 128

#endif
