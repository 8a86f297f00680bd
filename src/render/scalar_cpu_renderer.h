#pragma once
#include "render/cpu_renderer.h"
#include "render/scalar_kernel.h"
#include "render/scalar_rows.h"

namespace rt {

// The CPU renderers that run the scalar kernel (sequential, tbb_only): they
// differ only in how the image's spans are handed out.
class ScalarCPURenderer : public CPURenderer {
 public:
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override {
    CPURenderer::prepare(scene, extent, options);
    inputs_ = kernel::ShadingInputs<float>::from(scene);
  }

 protected:
  // One frame: `forEachSpan(span)` must call span(y, x0, x1) once for every
  // span of pixels x0..x1-1 of row y that together cover the image. The
  // kernel variant is chosen once per frame, never per ray.
  template <typename ForEachSpan>
  void renderSpans(const CameraFrame& camera, ForEachSpan&& forEachSpan) {
    const Extent e = extent();
    Image& frame = workingBuffer();
    visitScalarVariant(options(), [&]<Algorithm kAlgorithm, bool kBounce>() {
      forEachSpan([&](int y, int x0, int x1) {
        renderScalarSpan<float, kAlgorithm, kBounce>(inputs_, camera, e, y, x0, x1, frame.row(y));
      });
    });
  }

 private:
  kernel::ShadingInputs<float> inputs_{};
};

}  // namespace rt
