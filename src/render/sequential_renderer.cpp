#include "render/sequential_renderer.h"

#include "render/row_bands.h"
#include "render/scalar_rows.h"

namespace rt {

RendererInfo SequentialRenderer::info() const { return {RendererKind::sequential, 1, 1, "", std::nullopt, std::nullopt}; }

void SequentialRenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  CPURenderer::prepare(scene, extent, options);
  inputs_ = kernel::ShadingInputs<float>::from(scene);
}

void SequentialRenderer::render(const CameraFrame& camera) {
  const Extent e = extent();
  Image& frame = workingBuffer();
  visitScalarVariant(options(), [&]<Algorithm kAlgorithm, bool kBounce>() {
    forEachRowBand(e.height, [&](int y) {
      renderScalarRow<float, kAlgorithm, kBounce>(inputs_, camera, e, y, frame.row(y));
    });
  });
}

}  // namespace rt
