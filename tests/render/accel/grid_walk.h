#pragma once
// The GPU renderer's grid walk (nearestHitInGrid, shaders/nearest_hit.glsl)
// in C++, step for step, so that tests can hold the grid to brute force's
// nearest hit for thousands of rays on the CPU and try walks on grids built
// with other margins (docs/render-model.md section 3, "The grid"). The
// images of the walk itself are tested on the device
// (tests/gpu/compute/gpu_variants_test.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
#include <limits>
#include <span>

#include "render/accel/bvh.h"
#include "render/accel/sphere_grid.h"
#include "render/scalar/sphere_query.h"

namespace rt::test {

struct GridHit {
  float t = std::numeric_limits<float>::infinity();
  int sphere = -1;
};

// The shader's testLeafSphere: the best hit so far against sphere `index`
// hit at `t`, ties to the lower index.
inline void considerHit(GridHit& best, float t, int index) {
  if (t > kernel::kEpsilon<float> && t <= best.t && (t < best.t || index < best.sphere)) best = {t, index};
}

// The plane of cell boundary k on one axis, as a distance along the ray.
inline float gridPlaneDistance(const SphereGrid& grid, int axis, int k, const kernel::Ray<float>& ray,
                               const glm::vec3& inverse) {
  return (grid.origin[axis] + static_cast<float>(k) * grid.cellSize - ray.origin[axis]) * inverse[axis];
}

// nearestHitInGrid: the spheres kept apart, then the cells in the ray's
// order until the next starts behind the best hit + the walk's pad.
inline GridHit nearestHitInGrid(const kernel::Ray<float>& ray, std::span<const Sphere> spheres,
                                const SphereGrid& grid) {
  GridHit best;
  const auto test = [&](std::uint32_t slot) {
    const std::uint32_t index = grid.slots[slot];
    considerHit(best, kernel::intersectSphere(ray, spheres[index]), static_cast<int>(index));
  };
  for (std::uint32_t k = 0; k < grid.apartCount; ++k) test(k);
  const glm::vec3 a = glm::abs(ray.origin);
  const float pad = traversalPad(grid.walkPad, std::max({a.x, a.y, a.z}));
  const glm::vec3 inverse = kernel::inverseDirection(ray.direction);
  const glm::vec3 lo = grid.origin;
  const glm::vec3 hi = grid.origin + glm::vec3(grid.cells) * grid.cellSize;
  const glm::vec3 t0 = (lo - ray.origin) * inverse;
  const glm::vec3 t1 = (hi - ray.origin) * inverse;
  const glm::vec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
  const float enter = std::max({near.x, near.y, near.z});
  const float leave = std::min({far.x, far.y, far.z});
  if (!(enter <= leave && leave >= -pad && enter <= best.t + pad)) return best;
  const glm::vec3 start = enter > 0.0f ? ray.origin + enter * ray.direction : ray.origin;
  const glm::vec3 scaled = glm::floor((start - grid.origin) * (1.0f / grid.cellSize));
  glm::ivec3 cell = glm::ivec3(glm::clamp(scaled, glm::vec3(0.0f), glm::vec3(grid.cells - 1)));
  const glm::ivec3 step(inverse.x >= 0.0f ? 1 : -1, inverse.y >= 0.0f ? 1 : -1, inverse.z >= 0.0f ? 1 : -1);
  const glm::ivec3 ahead = glm::max(step, glm::ivec3(0));
  glm::vec3 next;
  for (int axis = 0; axis < 3; ++axis)
    next[axis] = gridPlaneDistance(grid, axis, cell[axis] + ahead[axis], ray, inverse);
  while (true) {
    const std::size_t number = grid.cellNumber(cell);
    for (std::uint32_t slot = grid.cellFirst[number]; slot < grid.cellFirst[number + 1]; ++slot) test(slot);
    if (std::min({next.x, next.y, next.z}) > best.t + pad) break;
    const int axis = next.x <= next.y && next.x <= next.z ? 0 : (next.y <= next.z ? 1 : 2);
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= grid.cells[axis]) break;
    next[axis] = gridPlaneDistance(grid, axis, cell[axis] + ahead[axis], ray, inverse);
  }
  return best;
}

}  // namespace rt::test
