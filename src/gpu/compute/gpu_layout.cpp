#include "gpu/compute/gpu_layout.h"

namespace rt::gpu {

std::vector<GPUSphere> toGpuSpheres(std::span<const Sphere> spheres) {
  std::vector<GPUSphere> out;
  out.reserve(spheres.size());
  for (const Sphere& s : spheres) out.push_back({s.position, s.radius, s.color});
  return out;
}

// Every shading parameter but maxDepth (a specialization constant) is a
// push constant: a new one must be added here and to RT_FRAME_CONSTANTS.
static_assert(sizeof(ShadingParams) == 4 * sizeof(glm::vec3) + 3 * sizeof(float) + sizeof(int),
              "a shading parameter was added: pass it to the shader");

FrameConstants makeFrameConstants(const ShadingParams& shading, std::uint32_t sphereCount, const CameraFrame& camera,
                                  Extent extent) {
  // One line per 16-byte slot of the block (the formatter would give each
  // member a line of its own).
  // clang-format off
  return {.cameraPosition = camera.position, .tanHalfFov = camera.tanHalfFov,
          .cameraForward = camera.forward, .width = extent.width,
          .cameraRight = camera.right, .height = extent.height,
          .cameraUp = camera.up, .sphereCount = sphereCount,
          .toLight = shading.toLight, .reflectivity = shading.reflectivity,
          .lightColor = shading.lightColor, .shininess = shading.shininess,
          .ambientColor = shading.ambientColor, .specularStrength = shading.specularStrength,
          .background = shading.background, .wavefrontDepth = 0};
  // clang-format on
}

}  // namespace rt::gpu
