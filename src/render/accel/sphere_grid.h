#pragma once
// A uniform grid over a scene's spheres, built once per scene for the GPU
// renderer's grid walk (--gpu-bvh grid; docs/render-model.md section 3,
// "The grid"). Cubic cells whose side is a power of two, from an origin that
// is a multiple of it: every cell plane is then an exact float, so the
// shader and this build agree on which cell a point lies in. A cell lists
// every sphere whose surface, widened by the build's margin, may pass
// through it.
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "scene/scene.h"

namespace rt {

struct SphereGrid {
  glm::vec3 origin{0.0f};  // the corner of cell (0, 0, 0): a multiple of cellSize
  float cellSize = 1.0f;   // a power of two
  glm::ivec3 cells{1};     // cells per axis
  // Cell (x, y, z) is number (z * cells.y + y) * cells.x + x; its spheres
  // are slots cellFirst[n] .. cellFirst[n + 1] - 1 of `slots`, which holds
  // sphere indices, ascending within a cell.
  std::vector<std::uint32_t> cellFirst;
  std::vector<std::uint32_t> slots;
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
};

// How the build sizes the cells: the power of two nearest (in log scale) to
// the side of a cube that holds `spheresPerCell` sphere centres on average
// over the spheres' bounding box; doubled while the grid would hold more
// than `maxCellsPerSphere` cells per sphere (a scene of a few far-apart
// spheres) or a cell plane would lie more than 2^23 cells from zero (where
// planes stop being exact floats).
struct SphereGridRule {
  double spheresPerCell = 1.0;
  double maxCellsPerSphere = 32.0;
};

// `margin`: how far past a sphere's surface a cell may lie and still list
// it, at least every ray's traversal pad (rt::sceneTraversalPad) so that a
// float hit point that lies a little off the sphere still lies in a cell
// that lists it. The build adds 2^-8 of a cell on top, for the shader's
// float steps from cell to cell.
SphereGrid buildSphereGrid(std::span<const Sphere> spheres, float margin, SphereGridRule rule = {});

}  // namespace rt
