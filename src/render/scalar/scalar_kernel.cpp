#include "render/scalar/scalar_kernel.h"

#include "render/scalar/scalar_span.h"

namespace rt {

void ScalarKernel::prepare(const Scene& scene, const RenderOptions& asked, int /*slots*/) {
  RenderOptions options = asked;
  options.accel = accel_.prepare(scene.spheres, asked.accel);
  inputs_ = kernel::ShadingInputs<float>::from(scene, accel_.bvh());
  visitScalarVariant(options, [&]<Algorithm kAlgorithm, bool kBounce, Accel kAccel>() {
    span_ = &renderScalarSpan<float, kAlgorithm, kBounce, kAccel>;
  });
}

}  // namespace rt
