// The GPU grid walk's grid (render/accel/sphere_grid.h): exact cell planes,
// every sphere listed by exactly the cells its surface passes within its own
// margin of, huge spheres kept apart, and the walk (its C++ twin,
// grid_walk.h) finding brute force's nearest hit for rays from anywhere.
// Its images are checked against brute force in
// tests/gpu/compute/gpu_variants_test.cpp.
#include "render/accel/sphere_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "render/accel/grid_walk.h"
#include "render/extreme_scenes.h"
#include "scene/camera.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr float kMargin = 0.01f;

std::vector<float> uniformMargins(std::span<const Sphere> spheres, float margin) {
  return std::vector<float>(spheres.size(), margin);
}

// The margins the GPU renderer lists by (gridFor()): each sphere's own pad
// for every origin the scene's rays can have.
std::vector<float> sceneMargins(const Scene& scene) {
  const Bvh bvh = buildBvh(scene.spheres);
  return sphereGridMargins(scene.spheres, originBound(bvh.maxCoordinate, cameraMaxCoordinate(scene.camera)));
}

bool lists(const SphereGrid& grid, std::size_t cell, std::uint32_t sphere) {
  const auto first = grid.slots.begin() + grid.cellFirst[cell];
  const auto last = grid.slots.begin() + grid.cellFirst[cell + 1];
  return std::binary_search(first, last, sphere);
}

bool keptApart(const SphereGrid& grid, std::uint32_t sphere) {
  return std::ranges::find(grid.apart(), sphere) != grid.apart().end();
}

std::vector<test::NamedScene> gridScenes() {
  std::vector<test::NamedScene> scenes;
  for (const char* name : test::kSceneNames) scenes.push_back({name, test::loadNamedScene(name)});
  for (const char* name : test::kCorpusSceneNames) scenes.push_back({name, test::loadNamedScene(name)});
  for (auto& s : test::adversarialScenes()) scenes.push_back(std::move(s));
  // A large sphere among small ones: many whole cells inside it.
  std::vector<Sphere> large = test::randomSpheres(1000, 12, 0.4f);
  large.push_back({{0, 0, 0}, 6, {1, 1, 1}});
  scenes.push_back({"large-among-small", test::withSpheres(large)});
  return scenes;
}

TEST(SphereGrid, CellPlanesAreExactFloats) {
  for (const auto& [name, scene] : gridScenes()) {
    const SphereGrid grid = buildSphereGrid(scene.spheres, sceneMargins(scene));
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

// Points on each listed sphere's surface and up to its margin off it, a
// spiral of directions: each lies in a cell that lists the sphere. A sphere
// kept apart is listed by no cell.
TEST(SphereGrid, EveryCellTheWidenedSurfaceCrossesListsTheSphere) {
  for (const auto& [name, scene] : gridScenes()) {
    const std::vector<float> margins = sceneMargins(scene);
    const SphereGrid grid = buildSphereGrid(scene.spheres, margins);
    for (std::uint32_t i = 0; i < scene.spheres.size(); ++i) {
      if (keptApart(grid, i)) {
        EXPECT_EQ(std::ranges::count(std::span(grid.slots).subspan(grid.apartCount), i), 0) << name << " " << i;
        continue;
      }
      const Sphere& s = scene.spheres[i];
      for (int k = 0; k < 64; ++k) {
        const double z = 1.0 - (2.0 * k + 1.0) / 64.0;
        const double angle = 2.399963 * k;  // the golden angle
        const double ring = std::sqrt(1.0 - z * z);
        const glm::dvec3 direction(ring * std::cos(angle), ring * std::sin(angle), z);
        for (const double off : {-double(margins[i]), 0.0, double(margins[i])}) {
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

// A cell lists a sphere exactly where the sphere's surface passes within
// the sphere's own margin (and the build's 2^-8 of a cell) of it: no whole
// boxes, no cells deep inside a large sphere, no cell another sphere's
// margin would reach. The slots of a cell ascend. Cells within 1e-9 of the
// bound are left to the build's rounding.
TEST(SphereGrid, ListsEachSphereInExactlyTheCellsWithinItsOwnMargin) {
  for (const auto& [name, scene] : gridScenes()) {
    const std::vector<float> margins = sceneMargins(scene);
    const SphereGrid grid = buildSphereGrid(scene.spheres, margins);
    const double side = grid.cellSize;
    ASSERT_EQ(grid.cellFirst.size(), grid.cellCount() + 1) << name;
    EXPECT_EQ(grid.cellFirst.back(), grid.slots.size()) << name;
    EXPECT_EQ(grid.cellFirst.front(), grid.apartCount) << name;
    std::size_t checked = 0;
    for (std::uint32_t i = 0; i < scene.spheres.size(); ++i) {
      if (keptApart(grid, i)) continue;
      const Sphere& s = scene.spheres[i];
      const glm::dvec3 c(s.position);
      const double reach = margins[i] + side / 256.0;
      const glm::ivec3 first =
          glm::max(glm::ivec3(glm::floor((c - (s.radius + 2 * reach) - glm::dvec3(grid.origin)) / side)), 0);
      const glm::ivec3 last = glm::min(
          glm::ivec3(glm::floor((c + (s.radius + 2 * reach) - glm::dvec3(grid.origin)) / side)), grid.cells - 1);
      for (int z = first.z; z <= last.z; ++z) {
        for (int y = first.y; y <= last.y; ++y) {
          for (int x = first.x; x <= last.x; ++x) {
            const glm::dvec3 lo = glm::dvec3(grid.origin) + glm::dvec3(x, y, z) * side;
            const double nearest = glm::length(glm::clamp(c, lo, lo + side) - c);
            const double farthest = glm::length(glm::max(glm::abs(lo - c), glm::abs(lo + side - c)));
            const double off = std::max(nearest - s.radius, s.radius - farthest);  // cell to surface
            if (std::abs(off - reach) < 1e-9 * (1.0 + s.radius)) continue;
            EXPECT_EQ(lists(grid, grid.cellNumber({x, y, z}), i), off <= reach)
                << name << " sphere " << i << " cell " << x << "," << y << "," << z << ": " << off << " off, margin "
                << reach;
            ++checked;
          }
        }
      }
    }
    EXPECT_GT(checked, 0u) << name;
    for (std::size_t cell = 0; cell < grid.cellCount(); ++cell) {
      const auto first = grid.slots.begin() + grid.cellFirst[cell];
      EXPECT_TRUE(std::is_sorted(first, grid.slots.begin() + grid.cellFirst[cell + 1])) << name;
    }
  }
}

// A cell at distance d from a sphere's surface lists it with a margin of d
// less the 2^-8 of a cell, and no longer one float step below: the margin
// is the bound itself, not a rough one. A lattice of 64 spheres gives cells
// of side 1 with planes on the integers; a probe sphere's top lies d below
// the plane y = 3.
TEST(SphereGrid, AMarginOneFloatStepShortDropsTheCellAtThatDistance) {
  std::vector<Sphere> spheres;
  for (int i = 0; i < 64; ++i) {
    spheres.push_back({{float(i % 4), float(i / 4 % 4), float(i / 16)}, 0.25f, {1, 1, 1}});
  }
  const float margin = 0x1p-6f;
  const double distance = 0x1p-6 + 0x1p-8;  // the margin and 2^-8 of a side of 1
  spheres.push_back({{1.5f, static_cast<float>(3.0 - distance - 0.25), 1.5f}, 0.25f, {1, 0, 0}});
  ASSERT_EQ(double(spheres.back().position.y), 3.0 - distance - 0.25) << "the probe lies exactly there";
  const auto probe = static_cast<std::uint32_t>(spheres.size() - 1);
  std::vector<float> margins = uniformMargins(spheres, margin);
  const SphereGrid reaching = buildSphereGrid(spheres, margins);
  ASSERT_EQ(reaching.cellSize, 1.0f);
  const glm::ivec3 above = glm::ivec3(glm::floor(glm::vec3(1.5f, 3.5f, 1.5f) - reaching.origin));
  const glm::ivec3 below = above - glm::ivec3(0, 1, 0);
  EXPECT_TRUE(lists(reaching, reaching.cellNumber(above), probe));
  margins[probe] = std::nextafter(margin, 0.0f);
  const SphereGrid shortOfIt = buildSphereGrid(spheres, margins);
  ASSERT_EQ(shortOfIt.origin, reaching.origin);
  ASSERT_EQ(shortOfIt.cells, reaching.cells);
  EXPECT_FALSE(lists(shortOfIt, shortOfIt.cellNumber(above), probe));
  EXPECT_TRUE(lists(shortOfIt, shortOfIt.cellNumber(below), probe)) << "the cell holding its top";
}

// A sphere's margin is its own pad: at least traversalPad of its radius and
// |coordinate| for every origin up to the bound, and on the ground scene the
// small spheres' margins are a hundredth of the scene's pad.
TEST(SphereGrid, MarginsAreEachSpheresOwnPad) {
  const Scene ground = test::groundUnderSmallSpheres();
  const Bvh bvh = buildBvh(ground.spheres);
  const float bound = originBound(bvh.maxCoordinate, cameraMaxCoordinate(ground.camera));
  const std::vector<float> margins = sphereGridMargins(ground.spheres, bound);
  const float scenePad = sceneTraversalPad(bvh.maxRadius, bvh.maxCoordinate, cameraMaxCoordinate(ground.camera));
  for (std::size_t i = 0; i < ground.spheres.size(); ++i) {
    const Sphere& s = ground.spheres[i];
    const glm::vec3 far = glm::max(glm::abs(s.position - s.radius), glm::abs(s.position + s.radius));
    const float coordinate = std::max({far.x, far.y, far.z});
    for (const float origin : {0.0f, 1.0f, 0.5f * bound, bound}) {
      EXPECT_GE(margins[i], traversalPad(s.radius, coordinate, origin)) << i << " from " << origin;
    }
    if (s.radius < 1.0f) {
      EXPECT_LT(margins[i], 0.02f * scenePad) << i;
    }
  }
  EXPECT_FLOAT_EQ(margins[0], scenePad) << "the ground's own pad is the scene's";
}

// Spheres whose widened box spans more than SphereGridRule::apartCells
// cells are kept apart, the largest maxApart of them at most; the grid's
// box and the walk's pad then follow the rest.
TEST(SphereGrid, KeepsHugeSpheresApart) {
  const Scene ground = test::groundUnderSmallSpheres();
  const SphereGrid grid = buildSphereGrid(ground.spheres, sceneMargins(ground));
  EXPECT_EQ(std::vector(grid.apart().begin(), grid.apart().end()), std::vector<std::uint32_t>{0}) << "the ground";
  EXPECT_LE(grid.cellSize, 1.0f) << "cells the size of the small spheres' spacing";
  EXPECT_LT(grid.origin.y, 0.0f);
  EXPECT_GE(grid.origin.y, -1.0f) << "the ground's bounds (down to y = -2000) are not the grid's";
  EXPECT_EQ(grid.walkPad.radius, 1.0f) << "the largest listed radius";
  EXPECT_LT(grid.walkPad.coordinate, 10.0f);
  EXPECT_EQ(grid.walkPad.originSlope, 0.0f);

  const Scene crowd = test::loadNamedScene("crowd500");
  const SphereGrid crowdGrid = buildSphereGrid(crowd.spheres, sceneMargins(crowd));
  ASSERT_EQ(crowdGrid.apartCount, 13u) << "the huge sphere and the ring of 12";
  for (const std::uint32_t i : crowdGrid.apart()) EXPECT_GE(crowd.spheres[i].radius, 6.0f) << i;
  EXPECT_TRUE(std::ranges::is_sorted(crowdGrid.apart()));
  for (const char* uniform : {"random1000", "clusters500"}) {
    const Scene scene = test::loadNamedScene(uniform);
    EXPECT_EQ(buildSphereGrid(scene.spheres, sceneMargins(scene)).apartCount, 0u) << uniform;
  }
  // Twenty huge spheres: the rule keeps the largest apart, the rest listed.
  std::vector<Sphere> many = test::randomSpheres(500, 12, 0.4f);
  for (int i = 0; i < 20; ++i) many.push_back({{float(i), 0, 0}, 30.0f + 5.0f * float(i), {1, 1, 1}});
  const SphereGrid capped = buildSphereGrid(many, uniformMargins(many, kMargin), {.maxApart = 16});
  ASSERT_EQ(capped.apartCount, 16u);
  EXPECT_EQ(capped.apart().front(), 504u) << "the four smallest of the twenty stay listed";
}

// About one sphere per cell where most centres lie, but never more cells
// than the rule allows per sphere: two far-apart spheres get a coarse grid,
// not a billion cells.
TEST(SphereGrid, SizesItsCellsFromTheSpheresAndTheRule) {
  const Scene scene = test::loadNamedScene("random1000");
  const std::vector<float> margins = uniformMargins(scene.spheres, kMargin);
  const SphereGrid fine = buildSphereGrid(scene.spheres, margins, {.spheresPerCell = 0.125});
  const SphereGrid coarse = buildSphereGrid(scene.spheres, margins, {.spheresPerCell = 8.0});
  EXPECT_EQ(coarse.cellSize, 4.0f * fine.cellSize);
  EXPECT_GT(fine.cellCount(), 32 * coarse.cellCount());
  const std::vector<Sphere> apart{{{-1000.0f, 0, 0}, 0.5f, {1, 1, 1}}, {{1000.0f, 0, 0}, 0.5f, {1, 1, 1}}};
  const SphereGridRule rule{.spheresPerCell = 1.0, .maxCellsPerSphere = 8.0};
  const SphereGrid sparse = buildSphereGrid(apart, uniformMargins(apart, kMargin), rule);
  EXPECT_LE(static_cast<double>(sparse.cellCount()), rule.maxCellsPerSphere * 2 + 64);
  // A sphere smaller than a cell crosses at most 2 x 2 x 2 of them.
  EXPECT_GE(sparse.slots.size(), 2u);
  EXPECT_LE(sparse.slots.size(), 16u);
  // A layer of spheres (a ground's): cells the size of their spacing, not
  // of a cube holding the layer's volume.
  const Scene ground = test::loadNamedScene("ground500");
  EXPECT_EQ(buildSphereGrid(ground.spheres, sceneMargins(ground)).cellSize, 1.0f);
  EXPECT_THROW(buildSphereGrid(apart, uniformMargins(scene.spheres, kMargin)), std::invalid_argument);
}

// Spheres far from the origin get cells coarse enough that every plane is
// still an exact float (at most 2^24 cells from zero), and tiny spheres
// there are still listed where their surface lies.
TEST(SphereGrid, StaysExactFarFromTheOrigin) {
  std::vector<Sphere> far;
  for (int i = 0; i < 50; ++i) far.push_back({{1e7f + static_cast<float>(i) * 0.01f, 3e6f, -2e6f}, 1e-3f, {1, 1, 1}});
  const SphereGrid grid = buildSphereGrid(far, uniformMargins(far, kMargin));
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(std::abs(grid.origin[axis] / grid.cellSize) + static_cast<float>(grid.cells[axis]), 0x1p24f) << axis;
  }
  for (std::uint32_t i = 0; i < far.size(); ++i) {
    const glm::ivec3 cell(glm::floor((glm::dvec3(far[i].position) - glm::dvec3(grid.origin)) / double(grid.cellSize)));
    EXPECT_TRUE(lists(grid, grid.cellNumber(cell), i)) << i;
  }
}

glm::vec3 unitDirection(std::uint32_t i, std::uint32_t salt) {
  return glm::normalize(
      glm::vec3(test::unitNoise(i, salt), test::unitNoise(i, salt + 1), test::unitNoise(i, salt + 2)) - 0.5f);
}

// The walk, listing by each sphere's own margin and stopping by the listed
// spheres' pad, finds brute force's nearest sphere (ties to the lower index)
// for camera rays and rays from sphere surfaces in every direction, on the
// committed, corpus, adversarial and extreme scenes.
TEST(SphereGrid, TheWalkFindsBruteForcesHitForRaysFromAnywhere) {
  std::vector<test::NamedScene> scenes = gridScenes();
  for (const char* name : test::kExtremeSceneNames) {
    if (std::string(name) != "100000-small") scenes.push_back({name, test::extremeScene(name)});
  }
  for (const auto& [name, scene] : scenes) {
    const SphereGrid grid = buildSphereGrid(scene.spheres, sceneMargins(scene));
    int differ = 0;
    for (std::uint32_t i = 0; i < 4000; ++i) {
      const Sphere& from = scene.spheres[i % scene.spheres.size()];
      const glm::vec3 d = unitDirection(i, 11);
      const kernel::Ray<float> ray = i % 2 == 1
                                         ? kernel::Ray<float>{scene.camera.position, d}
                                         : kernel::Ray<float>{from.position + from.radius * d, unitDirection(i, 14)};
      const auto want = kernel::nearestHitOfAll(ray, std::span<const Sphere>(scene.spheres));
      const test::GridHit got = test::nearestHitInGrid(ray, scene.spheres, grid);
      if (got.sphere != want.sphere || (want.hit() && got.t != want.distance)) ++differ;
    }
    EXPECT_EQ(differ, 0) << name << " (" << grid.apartCount << " apart, " << grid.cellCount() << " cells)";
  }
}

}  // namespace
}  // namespace rt
