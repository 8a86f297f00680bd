#include "gpu/compute/gpu_layout.h"

namespace rt::gpu {

std::vector<GPUSphere> toGpuSpheres(std::span<const Sphere> spheres) {
  std::vector<GPUSphere> out;
  out.reserve(spheres.size());
  for (const Sphere& s : spheres) out.push_back({s.position, s.radius, s.color});
  return out;
}

FrameConstants makeFrameConstants(const Scene& scene, const CameraFrame& camera, Extent extent) {
  const LightData& light = scene.lightData;
  const RenderParams& render = scene.render;
  return {.cameraPosition = camera.position,
          .tanHalfFov = camera.tanHalfFov,
          .cameraForward = camera.forward,
          .width = extent.width,
          .cameraRight = camera.right,
          .height = extent.height,
          .cameraUp = camera.up,
          .sphereCount = static_cast<std::uint32_t>(scene.spheres.size()),
          // Negated here as the C++ kernel does (ShadingInputs::from): exact in float.
          .toLight = -light.directionalLightDirection,
          .reflectivity = render.reflectivity,
          .lightColor = light.directionalLightColor,
          .shininess = render.shininess,
          .ambientColor = light.ambientLightColor,
          .specularStrength = render.specularStrength,
          .background = render.background};
}

}  // namespace rt::gpu
