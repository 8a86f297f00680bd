#include "render/scalar/scalar_kernel.h"

#include "render/scalar/scalar_span.h"

namespace rt {

void ScalarKernel::prepare(const Scene& scene, const RenderOptions& options, int /*slots*/) {
  inputs_ = kernel::ShadingInputs<float>::from(scene);
  bvh_ = options.accel == Accel::bvh ? buildBvh(scene.spheres) : Bvh{};
  if (options.accel == Accel::bvh) inputs_.bvh = &bvh_;
  visitScalarVariant(options, [&]<Algorithm kAlgorithm, bool kBounce>() {
    span_ = &renderScalarSpan<float, kAlgorithm, kBounce>;
  });
}

}  // namespace rt
