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

// The push-constant block, one MEMBER(GLSL type, name, byte offset) per
// member: raytrace.comp declares the block from this list and
// src/gpu/compute/gpu_layout.h the C++ mirror (rt::gpu::FrameConstants), so the two
// cannot differ in a name, a type or an order. The shader places each
// member at the listed offset and the C++ side asserts that it lies there
// in the C++ struct too, so a wrong offset fails the build (glslang also
// rejects a misaligned one). The camera and image size change per frame,
// the rest (rt::ShadingParams less maxDepth, a specialization constant)
// per scene. Each vec3 shares its 16-byte slot with a scalar.
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
  MEMBER(vec3, background, 112)        \
  MEMBER(float, unused, 124)

#endif
