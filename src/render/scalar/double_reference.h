#pragma once
#include <optional>

#include "core/image.h"
#include "render/accel/bvh.h"
#include "render/render_options.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt {

// How the reference finds each ray's nearest sphere: both give the same
// image, byte for byte (tests/render/double_reference_test.cpp); brute force
// is the model's definition and the BVH what makes 100,000 spheres affordable.
enum class ReferenceSearch { bvh, brute_force };

// The render model evaluated in double precision: what the float renderers
// must agree with (docs/render-model.md section 8) and what the golden images
// hold. Built once per scene (the BVH, over the scene's spheres, which must
// outlive it); render() may then be called for any frame and options.
class DoubleReference {
 public:
  explicit DoubleReference(const Scene& scene, ReferenceSearch search = ReferenceSearch::bvh);

  // --accel in `options` is ignored: the reference's search is its own.
  [[nodiscard]] Image render(const CameraFrame& camera, Extent extent, const RenderOptions& options) const;

 private:
  const Scene* scene_;
  std::optional<Bvh> bvh_;  // absent for brute force and for a scene without spheres
};

// One frame of the reference, the BVH built for it.
Image renderDoubleReference(const Scene& scene, const CameraFrame& camera, Extent extent, const RenderOptions& options);

}  // namespace rt
