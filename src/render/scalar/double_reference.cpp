#include "render/scalar/double_reference.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <cmath>

#include "render/scalar/scalar_span.h"

namespace rt {

double doubleTraversalPad(const Bvh& bvh, double originMaxCoordinate) {
  const double m = static_cast<double>(bvh.maxCoordinate);
  const double r = static_cast<double>(bvh.maxRadius);
  const double scale = originMaxCoordinate + m;
  return std::ldexp(m, -22) + std::ldexp(scale + r, -40) + std::ldexp(std::sqrt(r * scale), -26) + 1e-300;
}

DoubleReference::DoubleReference(const Scene& scene, ReferenceSearch search) : scene_(&scene) {
  if (search == ReferenceSearch::bvh && !scene.spheres.empty())
    bvh_ = buildBvh(scene.spheres, kBvhLeaves, BoxPadding::scene);
}

Image DoubleReference::render(const CameraFrame& camera, Extent extent, const RenderOptions& options) const {
  Image image(extent);
  const Bvh* bvh = bvh_ ? &*bvh_ : nullptr;
  const auto inputs = kernel::ShadingInputs<double>::from(*scene_, bvh);
  const auto renderRows = [&]<Algorithm kAlgorithm, bool kBounce, Accel kAccel>() {
    // Rows are independent and each pixel's arithmetic is fixed, so spreading
    // them over threads changes no bit.
    tbb::parallel_for(tbb::blocked_range<int>(0, extent.height), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) {
        renderScalarRow<double, kAlgorithm, kBounce, kAccel>(inputs, camera, extent, y, image.row(y));
      }
    });
  };
  // The BVH walk in double finds exactly brute force's nearest hit: its boxes
  // are padded for the double test (render/scalar/double_traversal_pad.h) and
  // exact ties go to the lower index as in brute force (docs/render-model.md section 3).
  RenderOptions search = options;
  search.accel = bvh != nullptr ? Accel::bvh : Accel::none;
  visitScalarVariant(search, renderRows);
  return image;
}

Image renderDoubleReference(const Scene& scene, const CameraFrame& camera, Extent extent,
                            const RenderOptions& options) {
  return DoubleReference(scene).render(camera, extent, options);
}

}  // namespace rt
