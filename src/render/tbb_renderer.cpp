#include "render/tbb_renderer.h"

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

void TBBRenderer::render(const CameraFrame& camera) {
  const Extent e = extent();
  renderSpans(camera, [&](const auto& span) {
    scheduler_.forEachSpan(e, 1, [&](int /*slot*/, int y, int x0, int x1) { span(y, x0, x1); });
  });
}

}  // namespace rt
