#pragma once
// What a renderer reports about the acceleration structure its prepare()
// built: beside the BVH that fills it (render/accel/bvh.h), so the BVH needs
// nothing of the Renderer interface (render/renderer.h), which reports it.
#include <cstddef>

#include "render/render_options.h"

namespace rt {

// The acceleration structure prepare() built (metadata: accel_structure).
struct AccelStructureInfo {
  Accel kind = Accel::bvh;
  double buildMs = 0.0;
  std::size_t nodes = 0;
  int depth = 0;
};

}  // namespace rt
