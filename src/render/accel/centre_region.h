#pragma once
// Where a scene's spheres mostly lie: the box between the 5th and the 95th
// percentile of their centres on each axis. One huge sphere (a ground of
// radius 1000 under spheres of radius 0.2) or a few far-out ones then do not
// stand for the scene the way the box around every sphere would: the BVH's
// price takes each box's chance of being reached against this region
// (padPrice, render/accel/bvh.h), and the grid sizes its cells from the
// centres inside it (render/accel/sphere_grid.h).
#include <cstddef>
#include <glm/vec3.hpp>
#include <span>

#include "scene/scene.h"

namespace rt {

struct CentreRegion {
  glm::vec3 lo{0.0f};
  glm::vec3 hi{0.0f};
  std::size_t centres = 0;  // sphere centres inside lo..hi, bounds included
};

// The region of `spheres` (at least one).
CentreRegion typicalCentreRegion(std::span<const Sphere> spheres);

}  // namespace rt
