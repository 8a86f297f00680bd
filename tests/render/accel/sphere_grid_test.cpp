// The GPU grid walk's grid (render/accel/sphere_grid.h): exact cell planes,
// every sphere listed by every cell its widened surface passes through, and
// no cell listing a sphere whose surface is far from it. Its images are
// checked against brute force in tests/gpu/compute/gpu_variants_test.cpp.
#include "render/accel/sphere_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr float kMargin = 0.01f;

bool lists(const SphereGrid& grid, std::size_t cell, std::uint32_t sphere) {
  const auto first = grid.slots.begin() + grid.cellFirst[cell];
  const auto last = grid.slots.begin() + grid.cellFirst[cell + 1];
  return std::binary_search(first, last, sphere);
}

std::vector<test::NamedScene> gridScenes() {
  std::vector<test::NamedScene> scenes;
  for (const char* name : test::kSceneNames) scenes.push_back({name, test::loadNamedScene(name)});
  for (auto& s : test::adversarialScenes()) scenes.push_back(std::move(s));
  // A large sphere among small ones: many whole cells inside it.
  std::vector<Sphere> large = test::randomSpheres(1000, 12, 0.4f);
  large.push_back({{0, 0, 0}, 6, {1, 1, 1}});
  scenes.push_back({"large-among-small", test::withSpheres(large)});
  return scenes;
}

TEST(SphereGrid, CellPlanesAreExactFloats) {
  for (const auto& [name, scene] : gridScenes()) {
    const SphereGrid grid = buildSphereGrid(scene.spheres, kMargin);
    const float side = grid.cellSize;
    EXPECT_EQ(std::exp2(std::round(std::log2(side))), side) << name << ": the side is a power of two";
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(std::fmod(grid.origin[axis], side), 0.0f) << name << ": the origin is a multiple of the side";
      const float last = grid.origin[axis] + static_cast<float>(grid.cells[axis]) * side;
      EXPECT_EQ(static_cast<double>(last),
                static_cast<double>(grid.origin[axis]) + static_cast<double>(grid.cells[axis]) * side)
          << name;
    }
  }
}

// Points on each sphere's surface and up to the margin off it, a spiral of
// directions: each lies in a cell that lists the sphere.
TEST(SphereGrid, EveryCellTheWidenedSurfaceCrossesListsTheSphere) {
  for (const auto& [name, scene] : gridScenes()) {
    const SphereGrid grid = buildSphereGrid(scene.spheres, kMargin);
    for (std::uint32_t i = 0; i < scene.spheres.size(); ++i) {
      const Sphere& s = scene.spheres[i];
      for (int k = 0; k < 64; ++k) {
        const double z = 1.0 - (2.0 * k + 1.0) / 64.0;
        const double angle = 2.399963 * k;  // the golden angle
        const double ring = std::sqrt(1.0 - z * z);
        const glm::dvec3 direction(ring * std::cos(angle), ring * std::sin(angle), z);
        for (const double off : {-kMargin, 0.0f, kMargin}) {
          const glm::dvec3 p = glm::dvec3(s.position) + direction * (static_cast<double>(s.radius) + off);
          const glm::ivec3 cell(glm::floor((p - glm::dvec3(grid.origin)) / static_cast<double>(grid.cellSize)));
          ASSERT_TRUE(glm::all(glm::greaterThanEqual(cell, glm::ivec3(0))) && glm::all(glm::lessThan(cell, grid.cells)))
              << name << " sphere " << i << ": a surface point outside the grid";
          EXPECT_TRUE(lists(grid, grid.cellNumber(cell), i)) << name << " sphere " << i << " point " << k;
        }
      }
    }
  }
}

// A cell lists a sphere only where the sphere's surface passes within the
// margin (and the build's 2^-8 of a cell) of it: no whole boxes, no cells
// deep inside a large sphere. The slots of a cell ascend.
TEST(SphereGrid, CellsListOnlySpheresWhoseSurfaceIsNear) {
  for (const auto& [name, scene] : gridScenes()) {
    const SphereGrid grid = buildSphereGrid(scene.spheres, kMargin);
    const double side = grid.cellSize;
    const double reach = kMargin + side / 256.0 + 1e-9;
    ASSERT_EQ(grid.cellFirst.size(), grid.cellCount() + 1) << name;
    EXPECT_EQ(grid.cellFirst.back(), grid.slots.size()) << name;
    for (int z = 0; z < grid.cells.z; ++z) {
      for (int y = 0; y < grid.cells.y; ++y) {
        for (int x = 0; x < grid.cells.x; ++x) {
          const std::size_t cell = grid.cellNumber({x, y, z});
          const auto first = grid.slots.begin() + grid.cellFirst[cell];
          const auto last = grid.slots.begin() + grid.cellFirst[cell + 1];
          EXPECT_TRUE(std::is_sorted(first, last)) << name;
          const glm::dvec3 lo = glm::dvec3(grid.origin) + glm::dvec3(x, y, z) * side;
          for (auto slot = first; slot != last; ++slot) {
            const Sphere& s = scene.spheres[*slot];
            const glm::dvec3 c(s.position);
            const double nearest = glm::length(glm::clamp(c, lo, lo + side) - c);
            const double farthest = glm::length(glm::max(glm::abs(lo - c), glm::abs(lo + side - c)));
            EXPECT_LE(nearest, s.radius + reach) << name << " cell " << cell << " sphere " << *slot;
            EXPECT_GE(farthest, s.radius - reach) << name << " cell " << cell << " sphere " << *slot;
          }
        }
      }
    }
  }
}

// About one sphere per cell, but never more cells than the rule allows per
// sphere: two far-apart spheres get a coarse grid, not a billion cells.
TEST(SphereGrid, SizesItsCellsFromTheSpheresAndTheRule) {
  const Scene scene = test::loadNamedScene("random1000");
  const SphereGrid fine = buildSphereGrid(scene.spheres, kMargin, {.spheresPerCell = 0.125});
  const SphereGrid coarse = buildSphereGrid(scene.spheres, kMargin, {.spheresPerCell = 8.0});
  EXPECT_EQ(coarse.cellSize, 4.0f * fine.cellSize);
  EXPECT_GT(fine.cellCount(), 32 * coarse.cellCount());
  const std::vector<Sphere> apart{{{-1000.0f, 0, 0}, 0.5f, {1, 1, 1}}, {{1000.0f, 0, 0}, 0.5f, {1, 1, 1}}};
  const SphereGridRule rule{.spheresPerCell = 1.0, .maxCellsPerSphere = 8.0};
  const SphereGrid sparse = buildSphereGrid(apart, kMargin, rule);
  EXPECT_LE(static_cast<double>(sparse.cellCount()), rule.maxCellsPerSphere * 2 + 64);
  // A sphere smaller than a cell crosses at most 2 x 2 x 2 of them.
  EXPECT_GE(sparse.slots.size(), 2u);
  EXPECT_LE(sparse.slots.size(), 16u);
}

// Spheres far from the origin get cells coarse enough that every plane is
// still an exact float (at most 2^24 cells from zero), and tiny spheres
// there are still listed where their surface lies.
TEST(SphereGrid, StaysExactFarFromTheOrigin) {
  std::vector<Sphere> far;
  for (int i = 0; i < 50; ++i) far.push_back({{1e7f + static_cast<float>(i) * 0.01f, 3e6f, -2e6f}, 1e-3f, {1, 1, 1}});
  const SphereGrid grid = buildSphereGrid(far, kMargin);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(std::abs(grid.origin[axis] / grid.cellSize) + static_cast<float>(grid.cells[axis]), 0x1p24f) << axis;
  }
  for (std::uint32_t i = 0; i < far.size(); ++i) {
    const glm::ivec3 cell(glm::floor((glm::dvec3(far[i].position) - glm::dvec3(grid.origin)) / double(grid.cellSize)));
    EXPECT_TRUE(lists(grid, grid.cellNumber(cell), i)) << i;
  }
}

}  // namespace
}  // namespace rt
