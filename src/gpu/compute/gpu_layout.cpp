#include "gpu/compute/gpu_layout.h"

#include <algorithm>

namespace rt::gpu {

std::vector<GPUSphere> toGpuSpheres(std::span<const Sphere> spheres) {
  std::vector<GPUSphere> out;
  out.reserve(spheres.size());
  for (const Sphere& s : spheres) out.push_back({s.position, s.radius, s.color});
  return out;
}

namespace {

// The number each inner node of `bvh` takes in the GPU's array: inner nodes
// only, depth first, a node before its left subtree and that before its
// right one; leaves get none (kNoGpuNode).
constexpr std::uint32_t kNoGpuNode = ~0u;

std::vector<std::uint32_t> gpuNodeNumbers(const Bvh& bvh) {
  std::vector<std::uint32_t> number(bvh.nodes.size(), kNoGpuNode);
  std::uint32_t next = 0;
  std::vector<std::uint32_t> pending{0};  // the root, numbered even when it is a leaf
  while (!pending.empty()) {
    const std::uint32_t index = pending.back();
    pending.pop_back();
    number[index] = next++;
    const BvhNode& n = bvh.nodes[index];
    if (n.leaf()) continue;
    for (const std::uint32_t child : {n.first + 1, n.first}) {  // the left child comes off first
      if (!bvh.nodes[child].leaf()) pending.push_back(child);
    }
  }
  return number;
}

}  // namespace

std::vector<GpuBinaryNode> toGpuBinaryNodes(const Bvh& bvh, float boxPad) {
  const std::vector<std::uint32_t> number = gpuNodeNumbers(bvh);
  const auto innerCount =
      static_cast<std::size_t>(std::ranges::count_if(number, [](std::uint32_t k) { return k != kNoGpuNode; }));
  std::vector<GpuBinaryNode> out(innerCount);
  const auto child = [&](std::uint32_t index, glm::vec3& lo, std::uint32_t& word, glm::vec3& hi, std::uint32_t& count) {
    const BvhNode& n = bvh.nodes[index];
    lo = n.lo - boxPad;
    hi = n.hi + boxPad;
    word = n.leaf() ? n.first : number[index];
    count = n.leaf() ? n.count() : 0u;
  };
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    if (number[i] == kNoGpuNode) continue;
    const BvhNode& n = bvh.nodes[i];
    GpuBinaryNode& g = out[number[i]];
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
          .background = shading.background};
  // clang-format on
}

std::vector<glm::uvec2> toGpuGridCells(const SphereGrid& grid) {
  std::vector<glm::uvec2> cells(grid.cellCount());
  for (std::size_t n = 0; n < cells.size(); ++n) {
    cells[n] = glm::uvec2(grid.cellFirst[n], grid.cellFirst[n + 1] - grid.cellFirst[n]);
  }
  return cells;
}

}  // namespace rt::gpu
