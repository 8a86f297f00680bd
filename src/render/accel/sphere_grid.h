#pragma once
// A uniform grid over a scene's spheres, built once per scene for the GPU
// renderer's grid walk (--gpu-bvh grid; docs/render-model.md section 3,
// "The grid"). Cubic cells whose side is a power of two, from an origin that
// is a multiple of it: every cell plane is then an exact float, so the
// shader and this build agree on which cell a point lies in. A cell lists
// every sphere whose surface, widened by that sphere's own margin, may pass
// through it; spheres too large for the cells are kept apart, in a short
// list every ray tests before it walks the cells.
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "render/accel/bvh.h"
#include "scene/scene.h"

namespace rt {

struct SphereGrid {
  glm::vec3 origin{0.0f};  // the corner of cell (0, 0, 0): a multiple of cellSize
  float cellSize = 1.0f;   // a power of two
  glm::ivec3 cells{1};     // cells per axis
  // Slots 0 .. apartCount - 1 of `slots` hold the spheres kept apart, in
  // index order: listed in no cell, tested by every ray first. Cell (x, y,
  // z) is number (z * cells.y + y) * cells.x + x; its spheres are slots
  // cellFirst[n] .. cellFirst[n + 1] - 1 (from apartCount on), sphere
  // indices ascending within a cell.
  std::uint32_t apartCount = 0;
  std::vector<std::uint32_t> cellFirst;
  std::vector<std::uint32_t> slots;
  // The pad of the walk's stop rule and clip (rt::traversalPad of the
  // ray's origin): the largest radius and |coordinate| of the spheres the
  // cells list, which bounds the pad of any sphere the walk could still
  // meet behind its stop (the ones kept apart were tested before).
  TraversalPadModel walkPad;
  double buildMs = 0.0;  // wall time of buildSphereGrid()

  [[nodiscard]] std::size_t cellCount() const {
    return static_cast<std::size_t>(cells.x) * static_cast<std::size_t>(cells.y) * static_cast<std::size_t>(cells.z);
  }
  // The number of cell (x, y, z), as above (and as the shader numbers it).
  [[nodiscard]] std::size_t cellNumber(glm::ivec3 cell) const {
    return (static_cast<std::size_t>(cell.z) * static_cast<std::size_t>(cells.y) + static_cast<std::size_t>(cell.y)) *
               static_cast<std::size_t>(cells.x) +
           static_cast<std::size_t>(cell.x);
  }
  [[nodiscard]] std::span<const std::uint32_t> apart() const { return std::span(slots).first(apartCount); }
};

// How the build sizes the cells and which spheres it keeps apart. The side
// is the power of two nearest (in log scale) to the side of a cube that
// holds `spheresPerCell` sphere centres on average where most centres lie
// (render/accel/centre_region.h; an axis thinner than the side counts as
// one cell, so that a layer of spheres on a ground gets cells the size of
// their spacing), or the median sphere's diameter where that is wider. A
// sphere whose widened box would span more than
// `apartCells` cells is kept apart, the largest `maxApart` of them at most;
// the grid's box then follows the spheres it lists. The side is doubled
// while that box would hold more than `maxCellsPerSphere` cells per listed
// sphere (a scene of a few far-apart spheres) or a cell plane would lie more
// than 2^23 cells from zero (where planes stop being exact floats).
struct SphereGridRule {
  double spheresPerCell = 1.0;
  double maxCellsPerSphere = 32.0;
  double apartCells = 64.0;
  std::uint32_t maxApart = 16;
};

// Each sphere's margin: its own traversal pad (rt::traversalPad of its
// radius, its |coordinate| and `originBound`), which covers every ray from
// within originBound (rt::originBound of the scene: the camera's orbit and
// every sphere, those kept apart too) because the pad grows with all three
// (docs/render-model.md section 3, "The grid").
std::vector<float> sphereGridMargins(std::span<const Sphere> spheres, float originBound);

// `margins`, one per sphere: how far past a sphere's surface a cell may lie
// and still list it, at least the traversal pad of every ray that may hit
// the sphere, so that a float hit point that lies a little off the sphere
// still lies in a cell that lists it (sphereGridMargins()). The build adds
// 2^-8 of a cell on top, for the shader's float steps from cell to cell.
SphereGrid buildSphereGrid(std::span<const Sphere> spheres, std::span<const float> margins, SphereGridRule rule = {});

}  // namespace rt
