#include "gpu/compute/gpu_layout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

namespace {

// The grid of one axis of one node: the exponent and the children's plane
// bytes, lower planes decoding at or below the exact bound, upper ones at or
// above it. Tries the smallest exponent whose 255 steps span the node, then
// larger ones until every bound fits.
struct AxisGrid {
  int exponent = -126;
  std::array<std::uint8_t, kWideBvhWidth> lo{}, hi{};
};

bool quantize(float origin, float bound, float scale, bool upper, std::uint8_t& q) {
  const double steps = (static_cast<double>(bound) - origin) / scale;
  long long k = upper ? static_cast<long long>(std::ceil(steps)) : static_cast<long long>(std::floor(steps));
  k = std::clamp(k, 0LL, 255LL);
  while (!upper && k > 0 && decodePlane(origin, static_cast<std::uint8_t>(k), scale) > bound) --k;
  while (upper && k < 255 && decodePlane(origin, static_cast<std::uint8_t>(k), scale) < bound) ++k;
  q = static_cast<std::uint8_t>(k);
  const float decoded = decodePlane(origin, q, scale);
  return upper ? decoded >= bound : decoded <= bound;
}

AxisGrid gridOf(const WideBvhNode& node, int axis, float origin) {
  float top = origin;
  for (std::uint32_t c = 0; c < node.childCount; ++c) top = std::max(top, node.bounds[WideBvhNode::kHiX + axis][c]);
  const double span = static_cast<double>(top) - origin;
  int exponent = span > 0 ? std::max(-126, static_cast<int>(std::ceil(std::log2(span / 255.0)))) : -126;
  for (;; ++exponent) {
    if (exponent > 127) throw std::logic_error("wide BVH node too large to quantize");
    AxisGrid grid{.exponent = exponent};
    const float scale = std::ldexp(1.0f, exponent);
    bool fits = true;
    for (std::uint32_t c = 0; c < node.childCount && fits; ++c) {
      fits = quantize(origin, node.bounds[WideBvhNode::kLoX + axis][c], scale, false, grid.lo[c]) &&
             quantize(origin, node.bounds[WideBvhNode::kHiX + axis][c], scale, true, grid.hi[c]);
    }
    if (fits) return grid;
  }
}

}  // namespace

std::vector<GpuWideNode> toGpuWideNodes(const WideBvh& wide) {
  std::vector<GpuWideNode> out;
  out.reserve(wide.nodes.size());
  for (const WideBvhNode& node : wide.nodes) {
    GpuWideNode g{};
    g.exponentsAndCount = node.childCount << 24;
    for (int axis = 0; axis < 3; ++axis) {
      float origin = node.childCount ? node.bounds[WideBvhNode::kLoX + axis][0] : 0.0f;
      for (std::uint32_t c = 1; c < node.childCount; ++c)
        origin = std::min(origin, node.bounds[WideBvhNode::kLoX + axis][c]);
      const AxisGrid grid = gridOf(node, axis, origin);
      g.origin[axis] = origin;
      g.exponentsAndCount |= static_cast<std::uint32_t>(grid.exponent + 127) << (8 * axis);
      g.planes[WideBvhNode::kLoX + axis] = grid.lo;
      g.planes[WideBvhNode::kHiX + axis] = grid.hi;
    }
    for (std::uint32_t c = 0; c < node.childCount; ++c) g.child[c] = node.child[c].bits;
    out.push_back(g);
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
