#include "render/tbb_renderer.h"

#include "render/scalar_rows.h"

namespace rt {

TBBRenderer::TBBRenderer(const ParallelSettings& settings)
    : scheduler_(settings.threads, settings.grain, settings.partition) {}

RendererInfo TBBRenderer::info() const {
  return {.kind = RendererKind::tbb_only,
          .threads = scheduler_.threads(),
          .lanes = 1,
          .simdTarget = "",
          .grain = scheduler_.grain(),
          .partition = scheduler_.partition()};
}

void TBBRenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  CPURenderer::prepare(scene, extent, options);
  inputs_ = kernel::ShadingInputs<float>::from(scene);
}

void TBBRenderer::render(const CameraFrame& camera) {
  const Extent e = extent();
  Image& frame = workingBuffer();
  visitScalarVariant(options(), [&]<Algorithm kAlgorithm, bool kBounce>() {
    scheduler_.forEachSpan(e, 1, [&](int /*slot*/, int y, int x0, int x1) {
      renderScalarSpan<float, kAlgorithm, kBounce>(inputs_, camera, e, y, x0, x1, frame.row(y));
    });
  });
}

}  // namespace rt
