#pragma once
// The driver's acceleration structure over a scene's spheres, for the
// ray-tracing pipeline renderer: a bottom-level structure of one box per
// sphere (box i is sphere i, so the intersection shader's gl_PrimitiveID is
// the sphere's index) and a top-level one holding it once, untransformed.
#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "gpu/vulkan/resources.h"
#include "scene/scene.h"

namespace rt::gpu {

// A sphere's box as the driver reads it (VkAabbPositionsKHR's layout).
struct SphereBox {
  float lo[3];
  float hi[3];
};
static_assert(sizeof(SphereBox) == sizeof(VkAabbPositionsKHR));

// The boxes of `spheres`, each widened by the traversal pad of its own
// sphere (traversalPad of its radius and bounds, render/accel/bvh.h) for
// every origin the scene's rays can have, so that the driver's own box test
// cannot cull a sphere the model's float test would hit. The pad grows with
// the ray origins' largest |coordinate|: the camera's (`cameraBound`,
// cameraMaxCoordinate in scene/camera.h) or a sphere surface's, where
// reflected rays start.
std::vector<SphereBox> paddedSphereBoxes(std::span<const Sphere> spheres, float cameraBound);

// One level's structure and the buffer that holds it.
struct AccelerationLevel {
  Buffer storage;
  vk::raii::AccelerationStructureKHR handle;
};

class SphereAccelerationStructure {
 public:
  // Builds both levels on the device and waits for the builds; the boxes
  // and scratch memory go on return.
  SphereAccelerationStructure(const Device& device, CommandRunner& runner, const Scene& scene);

  [[nodiscard]] vk::AccelerationStructureKHR topLevel() const { return *top_.handle; }
  // Host time of the build (boxes, uploads, both builds and the wait).
  [[nodiscard]] double buildMs() const { return buildMs_; }
  // Device memory of both structures as the driver sized them.
  [[nodiscard]] std::uint64_t deviceBytes() const { return bottom_.storage.size() + top_.storage.size(); }

 private:
  SphereAccelerationStructure(const Device& device, CommandRunner& runner, const Scene& scene,
                              std::chrono::steady_clock::time_point start);

  AccelerationLevel bottom_;  // declared first: the top level refers to it
  AccelerationLevel top_;
  double buildMs_;
};

}  // namespace rt::gpu
