#pragma once
// C++ mirrors of the data shaders/raytrace.comp reads, byte for byte. The
// static_asserts pin every offset the shader declares, so a change on one
// side that is not made on the other fails to compile.
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "gpu_interface.h"
#include "render/accel/bvh.h"
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

// The BVH goes to the shader as it is built: rt::BvhNode is already the
// std430 layout the shader reads (two 16-byte halves, the uint after each
// vec3), and the order array is plain uints. Its encoding and depth limit
// are shaders/bvh_layout.h's, which both sides include.
static_assert(sizeof(BvhNode) == 32);
static_assert(offsetof(BvhNode, lo) == 0);
static_assert(offsetof(BvhNode, first) == 12);
static_assert(offsetof(BvhNode, hi) == 16);
static_assert(offsetof(BvhNode, meta) == 28);
static_assert(sizeof(decltype(Bvh::order)::value_type) == sizeof(std::uint32_t));

// The push-constant block: camera, light, sphere count, image size and
// shading parameters, all of which may change from frame to frame. Each vec3
// shares its 16-byte slot with a scalar, so the block fits the 128 bytes
// every Vulkan device guarantees.
struct FrameConstants {
  glm::vec3 cameraPosition;
  float tanHalfFov;
  glm::vec3 cameraForward;
  std::int32_t width;
  glm::vec3 cameraRight;
  std::int32_t height;
  glm::vec3 cameraUp;
  std::uint32_t sphereCount;
  glm::vec3 toLight;  // -directionalLightDirection
  float reflectivity;
  glm::vec3 lightColor;
  float shininess;
  glm::vec3 ambientColor;
  float specularStrength;
  glm::vec3 background;
  float unused = 0.0f;
};
static_assert(sizeof(FrameConstants) == RT_PUSH_CONSTANT_BYTES);
static_assert(offsetof(FrameConstants, cameraPosition) == 0);
static_assert(offsetof(FrameConstants, tanHalfFov) == 12);
static_assert(offsetof(FrameConstants, cameraForward) == 16);
static_assert(offsetof(FrameConstants, width) == 28);
static_assert(offsetof(FrameConstants, cameraRight) == 32);
static_assert(offsetof(FrameConstants, height) == 44);
static_assert(offsetof(FrameConstants, cameraUp) == 48);
static_assert(offsetof(FrameConstants, sphereCount) == 60);
static_assert(offsetof(FrameConstants, toLight) == 64);
static_assert(offsetof(FrameConstants, reflectivity) == 76);
static_assert(offsetof(FrameConstants, lightColor) == 80);
static_assert(offsetof(FrameConstants, shininess) == 92);
static_assert(offsetof(FrameConstants, ambientColor) == 96);
static_assert(offsetof(FrameConstants, specularStrength) == 108);
static_assert(offsetof(FrameConstants, background) == 112);
static_assert(offsetof(FrameConstants, unused) == 124);

// The specialization constants of one pipeline variant.
struct SpecializationConstants {
  std::uint32_t twoPass;     // VkBool32
  std::uint32_t bounceExit;  // VkBool32
  std::int32_t maxDepth;
  std::uint32_t useBvh = 0;  // VkBool32: --accel bvh
  float bvhMaxRadius = 0.0f;       // Bvh::maxRadius and maxCoordinate, for the
  float bvhMaxCoordinate = 0.0f;   // traversal pad; unused without the BVH
};

std::vector<GPUSphere> toGpuSpheres(std::span<const Sphere> spheres);

// Frame constants of one frame: the scene's light and shading, the frame's camera.
FrameConstants makeFrameConstants(const Scene& scene, const CameraFrame& camera, Extent extent);

}  // namespace rt::gpu
