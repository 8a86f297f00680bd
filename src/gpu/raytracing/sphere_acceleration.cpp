#include "gpu/raytracing/sphere_acceleration.h"

#include <algorithm>
#include <cmath>

#include "render/accel/bvh.h"
#include "scene/camera.h"

namespace rt::gpu {
namespace {

using PipelineStage = vk::PipelineStageFlagBits;
using Access = vk::AccessFlagBits;
using BufferUsage = vk::BufferUsageFlagBits;

constexpr vk::BufferUsageFlags kBuildInput =
    BufferUsage::eAccelerationStructureBuildInputReadOnlyKHR | BufferUsage::eShaderDeviceAddress;

// Vulkan-Hpp's unions take no designated initializers.
vk::DeviceOrHostAddressConstKHR deviceAddressOf(const Buffer& buffer) {
  vk::DeviceOrHostAddressConstKHR address;
  address.deviceAddress = buffer.deviceAddress();
  return address;
}

vk::DeviceSize alignUp(vk::DeviceSize value, vk::DeviceSize alignment) {
  return alignment == 0 ? value : (value + alignment - 1) / alignment * alignment;
}

vk::DeviceSize scratchAlignment(const Device& device) {
  const auto chain =
      device.physical()
          .getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceAccelerationStructurePropertiesKHR>();
  return chain.get<vk::PhysicalDeviceAccelerationStructurePropertiesKHR>()
      .minAccelerationStructureScratchOffsetAlignment;
}

// Builds one level from `geometry` (`primitives` boxes or instances) on the
// device and waits for it; the scratch buffer goes on return. The build's
// writes are made visible to later builds and to the ray-tracing shaders.
AccelerationLevel buildLevel(const Device& device, CommandRunner& runner, vk::AccelerationStructureTypeKHR type,
                             const vk::AccelerationStructureGeometryKHR& geometry, std::uint32_t primitives) {
  vk::AccelerationStructureBuildGeometryInfoKHR build{
      .type = type,
      .flags = vk::BuildAccelerationStructureFlagBitsKHR::ePreferFastTrace,
      .mode = vk::BuildAccelerationStructureModeKHR::eBuild,
      .geometryCount = 1,
      .pGeometries = &geometry};
  const vk::AccelerationStructureBuildSizesInfoKHR sizes = device.logical().getAccelerationStructureBuildSizesKHR(
      vk::AccelerationStructureBuildTypeKHR::eDevice, build, primitives);
  Buffer storage(device, sizes.accelerationStructureSize,
                 BufferUsage::eAccelerationStructureStorageKHR | BufferUsage::eShaderDeviceAddress,
                 MemoryUse::deviceLocal);
  vk::raii::AccelerationStructureKHR handle(
      device.logical(), vk::AccelerationStructureCreateInfoKHR{
                            .buffer = storage.handle(), .size = sizes.accelerationStructureSize, .type = type});
  const vk::DeviceSize alignment = scratchAlignment(device);
  const Buffer scratch(device, sizes.buildScratchSize + alignment,
                       BufferUsage::eStorageBuffer | BufferUsage::eShaderDeviceAddress, MemoryUse::deviceLocal);
  build.dstAccelerationStructure = *handle;
  build.scratchData.deviceAddress = alignUp(scratch.deviceAddress(), alignment);
  const vk::AccelerationStructureBuildRangeInfoKHR range{.primitiveCount = primitives};
  runner.run("acceleration structure build", [&](const vk::raii::CommandBuffer& cb) {
    cb.buildAccelerationStructuresKHR(build, &range);
    const vk::MemoryBarrier written{.srcAccessMask = Access::eAccelerationStructureWriteKHR,
                                    .dstAccessMask = Access::eAccelerationStructureReadKHR};
    cb.pipelineBarrier(PipelineStage::eAccelerationStructureBuildKHR,
                       PipelineStage::eAccelerationStructureBuildKHR | PipelineStage::eRayTracingShaderKHR, {}, written,
                       {}, {});
  });
  return {std::move(storage), std::move(handle)};
}

AccelerationLevel buildBottomLevel(const Device& device, CommandRunner& runner, const Scene& scene) {
  const std::vector<SphereBox> boxes = paddedSphereBoxes(scene.spheres, cameraMaxCoordinate(scene.camera));
  const Buffer boxBuffer = uploadToDevice(device, runner, std::as_bytes(std::span(boxes)), kBuildInput,
                                          PipelineStage::eAccelerationStructureBuildKHR, Access::eShaderRead);
  vk::AccelerationStructureGeometryDataKHR boxData;
  boxData.aabbs =
      vk::AccelerationStructureGeometryAabbsDataKHR{.data = deviceAddressOf(boxBuffer), .stride = sizeof(SphereBox)};
  // Opaque: no any-hit shader runs, the intersection shader's nearest report wins.
  const vk::AccelerationStructureGeometryKHR geometry{
      .geometryType = vk::GeometryTypeKHR::eAabbs, .geometry = boxData, .flags = vk::GeometryFlagBitsKHR::eOpaque};
  return buildLevel(device, runner, vk::AccelerationStructureTypeKHR::eBottomLevel, geometry,
                    static_cast<std::uint32_t>(boxes.size()));
}

AccelerationLevel buildTopLevel(const Device& device, CommandRunner& runner, const AccelerationLevel& bottom) {
  const vk::DeviceAddress bottomAddress = device.logical().getAccelerationStructureAddressKHR(
      vk::AccelerationStructureDeviceAddressInfoKHR{.accelerationStructure = *bottom.handle});
  // The identity transform: world rays reach the intersection shader unchanged.
  vk::AccelerationStructureInstanceKHR instance{};
  for (int row = 0; row < 3; ++row) instance.transform.matrix[row][row] = 1.0f;
  instance.mask = 0xFF;
  instance.accelerationStructureReference = bottomAddress;
  const Buffer instanceBuffer = uploadToDevice(device, runner, std::as_bytes(std::span(&instance, 1)), kBuildInput,
                                               PipelineStage::eAccelerationStructureBuildKHR, Access::eShaderRead);
  vk::AccelerationStructureGeometryDataKHR instances;
  instances.instances = vk::AccelerationStructureGeometryInstancesDataKHR{.arrayOfPointers = VK_FALSE,
                                                                          .data = deviceAddressOf(instanceBuffer)};
  const vk::AccelerationStructureGeometryKHR geometry{.geometryType = vk::GeometryTypeKHR::eInstances,
                                                      .geometry = instances,
                                                      .flags = vk::GeometryFlagBitsKHR::eOpaque};
  return buildLevel(device, runner, vk::AccelerationStructureTypeKHR::eTopLevel, geometry, 1);
}

}  // namespace

std::vector<SphereBox> paddedSphereBoxes(std::span<const Sphere> spheres, float cameraBound) {
  const auto boundOf = [](const Sphere& s) {
    return std::max({std::abs(s.position.x), std::abs(s.position.y), std::abs(s.position.z)}) + s.radius;
  };
  float maxCoordinate = 0.0f;
  for (const Sphere& s : spheres) maxCoordinate = std::max(maxCoordinate, boundOf(s));
  // Reflected rays start on the spheres' surfaces, camera rays at the camera;
  // each box takes the pad its own sphere's radius and bounds give
  // (docs/render-model.md section 3, "The traversal pad").
  const float origin = originBound(maxCoordinate, cameraBound);
  std::vector<SphereBox> boxes(spheres.size());
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const Sphere& s = spheres[i];
    const float pad = traversalPad(s.radius, boundOf(s), origin);
    for (int a = 0; a < 3; ++a) {
      boxes[i].lo[a] = s.position[a] - s.radius - pad;
      boxes[i].hi[a] = s.position[a] + s.radius + pad;
    }
  }
  return boxes;
}

SphereAccelerationStructure::SphereAccelerationStructure(const Device& device, CommandRunner& runner,
                                                         const Scene& scene)
    : SphereAccelerationStructure(device, runner, scene, std::chrono::steady_clock::now()) {}

SphereAccelerationStructure::SphereAccelerationStructure(const Device& device, CommandRunner& runner,
                                                         const Scene& scene,
                                                         std::chrono::steady_clock::time_point start)
    : bottom_(buildBottomLevel(device, runner, scene)),
      top_(buildTopLevel(device, runner, bottom_)),
      buildMs_(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()) {}

}  // namespace rt::gpu
