#include "render/scalar/double_reference.h"

#include "render/scalar/scalar_span.h"

namespace rt {

Image renderDoubleReference(const Scene& scene, const CameraFrame& camera, Extent extent,
                            const RenderOptions& options) {
  Image image(extent);
  const auto inputs = kernel::ShadingInputs<double>::from(scene);
  // Brute force whatever --accel says: the reference is the model itself,
  // and docs/render-model.md section 3 asks for the nearest hit, not a way to find it.
  visitScalarVariant(options, [&]<Algorithm kAlgorithm, bool kBounce, Accel>() {
    for (int y = 0; y < extent.height; ++y) {
      renderScalarRow<double, kAlgorithm, kBounce, Accel::none>(inputs, camera, extent, y, image.row(y));
    }
  });
  return image;
}

}  // namespace rt
