#include "render/scalar/double_reference.h"

#include "render/scalar/scalar_span.h"

namespace rt {

Image renderDoubleReference(const Scene& scene, const CameraFrame& camera, Extent extent,
                            const RenderOptions& options) {
  Image image(extent);
  const auto inputs = kernel::ShadingInputs<double>::from(scene);
  visitScalarVariant(options, [&]<Algorithm kAlgorithm, bool kBounce>() {
    for (int y = 0; y < extent.height; ++y) {
      renderScalarRow<double, kAlgorithm, kBounce>(inputs, camera, extent, y, image.row(y));
    }
  });
  return image;
}

}  // namespace rt
