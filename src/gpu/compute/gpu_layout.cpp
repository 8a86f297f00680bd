#include "gpu/compute/gpu_layout.h"

namespace rt::gpu {

std::vector<GPUSphere> toGpuSpheres(std::span<const Sphere> spheres) {
  std::vector<GPUSphere> out;
  out.reserve(spheres.size());
  for (const Sphere& s : spheres) out.push_back({s.position, s.radius, s.color});
  return out;
}

std::vector<GpuBinaryNode> toGpuBinaryNodes(const Bvh& bvh) {
  std::vector<GpuBinaryNode> out(bvh.nodes.size());
  const auto child = [&](std::uint32_t index, glm::vec3& lo, std::uint32_t& word, glm::vec3& hi, std::uint32_t& count) {
    const BvhNode& n = bvh.nodes[index];
    lo = n.lo;
    hi = n.hi;
    word = n.leaf() ? n.first : index;
    count = n.leaf() ? n.count() : 0u;
  };
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode& n = bvh.nodes[i];
    if (n.leaf() && i != 0) continue;
    GpuBinaryNode& g = out[i];
    const std::uint32_t left = n.leaf() ? 0u : n.first;
    const std::uint32_t right = n.leaf() ? 0u : n.first + 1;
    child(left, g.lo0, g.child0, g.hi0, g.count0);
    child(right, g.lo1, g.child1, g.hi1, g.count1);
  }
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
