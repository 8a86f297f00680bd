#pragma once
// What a renderer reports about the acceleration structure its prepare()
// built: beside the BVH that fills it (render/accel/bvh.h), so the BVH needs
// nothing of the Renderer interface (render/renderer.h), which reports it.
#include <cstddef>
#include <cstdint>
#include <optional>

#include "render/render_options.h"

namespace rt {

// The acceleration structure prepare() built (metadata: accel_structure).
struct AccelStructureInfo {
  Accel kind = Accel::bvh;
  double buildMs = 0.0;
  // Unknown for a driver's structure (the gpu_rt renderer's), whose layout
  // the driver keeps to itself.
  std::optional<std::size_t> nodes;
  std::optional<int> depth;
  // Device memory it takes; empty for structures in host memory.
  std::optional<std::uint64_t> deviceBytes;
  // The BVH's box padding and its estimated tests per ray (Bvh::price);
  // empty for the driver's structure.
  std::optional<BoxPadding> padding;
  std::optional<double> estimatedTestsPerRay;
  // The grid's spheres kept out of its cells (rt::SphereGrid::apartCount);
  // empty for the trees and the driver's structure.
  std::optional<std::uint32_t> spheresKeptApart;
};

}  // namespace rt
