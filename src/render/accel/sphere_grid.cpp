#include "render/accel/sphere_grid.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/accel/centre_region.h"

namespace rt {
namespace {

struct Bounds {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};

  [[nodiscard]] bool empty() const { return lo.x > hi.x; }
};

double cellsFor(const Bounds& b, double side) {
  const glm::dvec3 extent = (b.hi - b.lo) / side + 1.0;
  return std::ceil(extent.x) * std::ceil(extent.y) * std::ceil(extent.z);
}

// The largest |coordinate| of a sphere's box, as the BVH's build measures
// a box (float bounds, Bvh::maxCoordinate): its share of the pad.
float boxCoordinate(const Sphere& s) {
  const glm::vec3 lo = s.position - s.radius;
  const glm::vec3 hi = s.position + s.radius;
  const glm::vec3 far = glm::max(glm::abs(lo), glm::abs(hi));
  return std::max({far.x, far.y, far.z});
}

// The side of a cube holding `spheresPerCell` centres on average in the
// region where most centres lie; an axis of the region thinner than the
// side counts as one cell. With the region's extents e1 >= e2 >= e3 and k
// axes longer than the side s, the region holds e1 ... ek / s^k cells.
double densitySide(std::span<const Sphere> spheres, double spheresPerCell) {
  const CentreRegion region = typicalCentreRegion(spheres);
  std::array<double, 4> e{double(region.hi.x) - region.lo.x, double(region.hi.y) - region.lo.y,
                          double(region.hi.z) - region.lo.z, 0.0};
  std::sort(e.begin(), e.begin() + 3, std::greater<>());
  const double cellsWanted = static_cast<double>(region.centres) / spheresPerCell;
  double product = 1.0;
  for (std::size_t k = 1; k <= 3; ++k) {
    product *= e[k - 1];
    const double side = std::pow(product / cellsWanted, 1.0 / static_cast<double>(k));
    if (side <= e[k - 1] && side > e[k]) return side;
  }
  return e[0];  // fewer centres than a cell holds, or all of them at one point
}

// The density's side, or the median sphere's diameter where that is wider:
// a few large spheres close together (nested ones, a pile) would otherwise
// get cells so small that each spans too many to be listed.
double regionSide(std::span<const Sphere> spheres, double spheresPerCell) {
  std::vector<float> radii(spheres.size());
  std::ranges::transform(spheres, radii.begin(), [](const Sphere& s) { return s.radius; });
  const auto middle = radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2);
  std::ranges::nth_element(radii, middle);
  return std::max(densitySide(spheres, spheresPerCell), 2.0 * double(*middle));
}

// How many cells the box of a sphere widened by `margin` spans.
double cellsSpanned(const Sphere& s, double margin, double side) {
  const glm::dvec3 c(s.position);
  const double reach = s.radius + margin;
  const glm::dvec3 spans = glm::floor((c + reach) / side) - glm::floor((c - reach) / side) + 1.0;
  return spans.x * spans.y * spans.z;
}

// The grid's shape before its cells are filled: the side, which spheres are
// kept apart (index order), and the bounds of the listed spheres' surfaces
// widened by their margins and the side's 2^-8.
struct Layout {
  double side = 1.0;
  std::vector<std::uint32_t> apart;
  std::vector<bool> isApart;
  Bounds listed;
  std::size_t listedCount = 0;
};

// The spheres whose widened box spans more than rule.apartCells cells, the
// largest rule.maxApart of them (fewest cells spanned, then lower index,
// stay listed), in index order.
std::vector<std::uint32_t> spheresKeptApart(std::span<const Sphere> spheres, std::span<const float> margins,
                                            double side, const SphereGridRule& rule) {
  std::vector<std::pair<double, std::uint32_t>> large;
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const double spanned = cellsSpanned(spheres[i], margins[i], side);
    if (spanned > rule.apartCells) large.emplace_back(-spanned, i);
  }
  std::sort(large.begin(), large.end());
  if (large.size() > rule.maxApart) large.resize(rule.maxApart);
  std::vector<std::uint32_t> apart;
  for (const auto& [spanned, i] : large) apart.push_back(i);
  std::sort(apart.begin(), apart.end());
  return apart;
}

Layout layoutAt(std::span<const Sphere> spheres, std::span<const float> margins, double side,
                const SphereGridRule& rule) {
  Layout layout;
  layout.side = side;
  layout.apart = spheresKeptApart(spheres, margins, side, rule);
  layout.isApart.assign(spheres.size(), false);
  for (const std::uint32_t i : layout.apart) layout.isApart[i] = true;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    if (layout.isApart[i]) continue;
    const glm::dvec3 c(spheres[i].position);
    const double reach = double(spheres[i].radius) + margins[i] + side * 0x1p-8;
    layout.listed.lo = glm::min(layout.listed.lo, c - reach);
    layout.listed.hi = glm::max(layout.listed.hi, c + reach);
    ++layout.listedCount;
  }
  return layout;
}

// Whether the layout's box holds few enough cells per listed sphere, and
// every plane k * side in it is an exact float (k * side stays exact to
// 2^24 sides; 2 sides of room for the rounding of the bounds).
bool fits(const Layout& layout, const SphereGridRule& rule) {
  if (layout.listedCount == 0) return true;
  const double maxCells = rule.maxCellsPerSphere * static_cast<double>(layout.listedCount) + 64.0;
  const glm::dvec3 far = glm::max(glm::abs(layout.listed.lo), glm::abs(layout.listed.hi));
  const double farthest = std::max({far.x, far.y, far.z});
  return cellsFor(layout.listed, layout.side) <= maxCells && farthest / layout.side + 2.0 <= 0x1p23;
}

// The side from the region (SphereGridRule), doubled until the layout fits:
// a grid far from the origin gets coarser cells, never inexact planes.
Layout layoutFor(std::span<const Sphere> spheres, std::span<const float> margins, const SphereGridRule& rule) {
  double side = std::exp2(std::round(std::log2(regionSide(spheres, rule.spheresPerCell))));
  while (true) {
    Layout layout = layoutAt(spheres, margins, side, rule);
    if (fits(layout, rule)) return layout;
    side *= 2.0;
  }
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

// The slots: the spheres kept apart first, then each cell's listing, in
// sphere order within a cell.
void fillCells(std::span<const Sphere> spheres, std::span<const float> margins, const Layout& layout,
               SphereGrid& grid) {
  const double step = layout.side * 0x1p-8;
  const auto eachListed = [&](auto&& visit) {
    for (std::uint32_t i = 0; i < spheres.size(); ++i) {
      if (!layout.isApart[i]) forEachCellOf(spheres[i], margins[i] + step, grid, [&](std::size_t n) { visit(n, i); });
    }
  };
  std::vector<std::uint64_t> counts(grid.cellCount(), 0u);
  eachListed([&](std::size_t cell, std::uint32_t) { ++counts[cell]; });
  grid.apartCount = static_cast<std::uint32_t>(layout.apart.size());
  grid.cellFirst.assign(grid.cellCount() + 1, 0u);
  std::uint64_t total = grid.apartCount;
  for (std::size_t cell = 0; cell < grid.cellCount(); ++cell) {
    grid.cellFirst[cell] = static_cast<std::uint32_t>(total);
    total += counts[cell];
    if (total > std::numeric_limits<std::uint32_t>::max()) {
      throw std::runtime_error("the sphere grid would list more than 2^32 spheres");
    }
  }
  grid.cellFirst.back() = static_cast<std::uint32_t>(total);
  grid.slots.resize(total);
  std::copy(layout.apart.begin(), layout.apart.end(), grid.slots.begin());
  std::vector<std::uint32_t> next(grid.cellFirst.begin(), grid.cellFirst.end() - 1);
  eachListed([&](std::size_t cell, std::uint32_t i) { grid.slots[next[cell]++] = i; });
}

// The stop rule's pad model: the listed spheres' largest radius and
// |coordinate| (SphereGrid::walkPad).
TraversalPadModel walkPadOf(std::span<const Sphere> spheres, const Layout& layout) {
  TraversalPadModel pad;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    if (layout.isApart[i]) continue;
    pad.radius = std::max(pad.radius, spheres[i].radius);
    pad.coordinate = std::max(pad.coordinate, boxCoordinate(spheres[i]));
  }
  return pad;
}

}  // namespace

std::vector<float> sphereGridMargins(std::span<const Sphere> spheres, float originBound) {
  std::vector<float> margins(spheres.size());
  std::ranges::transform(spheres, margins.begin(),
                         [&](const Sphere& s) { return traversalPad(s.radius, boxCoordinate(s), originBound); });
  return margins;
}

SphereGrid buildSphereGrid(std::span<const Sphere> spheres, std::span<const float> margins, SphereGridRule rule) {
  const auto start = std::chrono::steady_clock::now();
  if (margins.size() != spheres.size()) {
    throw std::invalid_argument("the sphere grid needs one margin per sphere: " + std::to_string(margins.size()) +
                                " for " + std::to_string(spheres.size()));
  }
  SphereGrid grid;
  Layout layout;
  if (!spheres.empty()) layout = layoutFor(spheres, margins, rule);
  if (layout.listedCount > 0) {
    const double h = layout.side;
    const glm::dvec3 lo = glm::floor(layout.listed.lo / h) * h;
    grid.cellSize = static_cast<float>(h);
    grid.origin = glm::vec3(lo);
    grid.cells = glm::ivec3(glm::floor((layout.listed.hi - lo) / h) + 1.0);
  }
  layout.isApart.resize(spheres.size(), false);
  fillCells(spheres, margins, layout, grid);
  grid.walkPad = walkPadOf(spheres, layout);
  grid.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return grid;
}

}  // namespace rt
