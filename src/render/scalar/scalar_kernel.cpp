#include "render/scalar/scalar_kernel.h"

#include "render/scalar/scalar_span.h"

namespace rt {

void ScalarKernel::prepare(const Scene& scene, const RenderOptions& options, int /*slots*/) {
  inputs_ = kernel::ShadingInputs<float>::from(scene);
  accel_.prepare(scene.spheres, options.accel);
  inputs_.bvh = accel_.bvh();
  visitScalarVariant(options, [&]<Algorithm kAlgorithm, bool kBounce>() {
    span_ = &renderScalarSpan<float, kAlgorithm, kBounce>;
  });
}

}  // namespace rt
