#include "render/accel/sphere_grid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <limits>
#include <stdexcept>

namespace rt {
namespace {

struct Bounds {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
};

Bounds sphereBounds(std::span<const Sphere> spheres) {
  Bounds b;
  for (const Sphere& s : spheres) {
    const glm::dvec3 c(s.position);
    const double r = s.radius;
    b.lo = glm::min(b.lo, c - r);
    b.hi = glm::max(b.hi, c + r);
  }
  return b;
}

double cellsFor(const Bounds& b, double side) {
  const glm::dvec3 extent = (b.hi - b.lo) / side + 1.0;
  return std::ceil(extent.x) * std::ceil(extent.y) * std::ceil(extent.z);
}

// The cells a sphere's widened surface may pass through: those its widened
// box overlaps, less the ones that lie wholly outside the widened sphere or
// wholly inside the narrowed one (no point of such a cell is within
// `margin` of the surface). In double, on exact float cell planes.
template <typename Visit>
void forEachCellOf(const Sphere& s, double margin, const SphereGrid& grid, Visit&& visit) {
  const glm::dvec3 c(s.position);
  const double outer = s.radius + margin;
  const double inner = s.radius - margin;
  const double h = grid.cellSize;
  const glm::dvec3 origin(grid.origin);
  const auto cellOf = [&](glm::dvec3 p) {
    return glm::clamp(glm::ivec3(glm::floor((p - origin) / h)), glm::ivec3(0), grid.cells - 1);
  };
  const glm::ivec3 first = cellOf(c - outer);
  const glm::ivec3 last = cellOf(c + outer);
  for (int z = first.z; z <= last.z; ++z) {
    for (int y = first.y; y <= last.y; ++y) {
      for (int x = first.x; x <= last.x; ++x) {
        const glm::dvec3 lo = origin + glm::dvec3(x, y, z) * h;
        const glm::dvec3 hi = lo + h;
        const glm::dvec3 nearest = glm::clamp(c, lo, hi);
        const glm::dvec3 toNearest = nearest - c;
        if (glm::dot(toNearest, toNearest) > outer * outer) continue;
        const glm::dvec3 farthest = glm::max(glm::abs(lo - c), glm::abs(hi - c));
        if (inner > 0.0 && glm::dot(farthest, farthest) < inner * inner) continue;
        visit(grid.cellNumber({x, y, z}));
      }
    }
  }
}

// The side of the cells (SphereGridRule), raised where a cell plane k * side
// would lie more than 2^23 sides from zero (k * side stays an exact float
// to 2^24): a grid far from the origin gets coarser cells, never inexact
// planes.
double cellSizeFor(const Bounds& b, std::size_t count, SphereGridRule rule) {
  const glm::dvec3 extent = glm::max(b.hi - b.lo, glm::dvec3(1e-30));
  const double n = static_cast<double>(count);
  const double side = std::cbrt(extent.x * extent.y * extent.z * rule.spheresPerCell / n);
  double cellSize = std::exp2(std::round(std::log2(side)));
  const double maxCells = rule.maxCellsPerSphere * n + 64.0;
  const glm::dvec3 far = glm::max(glm::abs(b.lo), glm::abs(b.hi));
  const double farthest = std::max({far.x, far.y, far.z});
  while (cellsFor(b, cellSize) > maxCells || farthest / cellSize + 2.0 > 0x1p23) cellSize *= 2.0;
  return cellSize;
}

}  // namespace

SphereGrid buildSphereGrid(std::span<const Sphere> spheres, float margin, SphereGridRule rule) {
  const auto start = std::chrono::steady_clock::now();
  SphereGrid grid;
  double widened = margin;
  if (!spheres.empty()) {
    const Bounds b = sphereBounds(spheres);
    const double h = cellSizeFor(b, spheres.size(), rule);
    widened += h * 0x1p-8;
    const glm::dvec3 lo = glm::floor((b.lo - widened) / h) * h;
    grid.cellSize = static_cast<float>(h);
    grid.origin = glm::vec3(lo);
    grid.cells = glm::ivec3(glm::floor((b.hi + widened - lo) / h) + 1.0);
  }
  std::vector<std::uint32_t> counts(grid.cellCount() + 1, 0u);
  for (const Sphere& s : spheres) forEachCellOf(s, widened, grid, [&](std::size_t cell) { ++counts[cell]; });
  grid.cellFirst.assign(grid.cellCount() + 1, 0u);
  std::uint64_t total = 0;
  for (std::size_t cell = 0; cell < grid.cellCount(); ++cell) {
    grid.cellFirst[cell] = static_cast<std::uint32_t>(total);
    total += counts[cell];
    if (total > std::numeric_limits<std::uint32_t>::max()) {
      throw std::runtime_error("the sphere grid would list more than 2^32 spheres");
    }
  }
  grid.cellFirst.back() = static_cast<std::uint32_t>(total);
  grid.slots.resize(total);
  std::vector<std::uint32_t> next(grid.cellFirst.begin(), grid.cellFirst.end() - 1);
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    forEachCellOf(spheres[i], widened, grid,
                  [&](std::size_t cell) { grid.slots[next[cell]++] = static_cast<std::uint32_t>(i); });
  }
  grid.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return grid;
}

}  // namespace rt
