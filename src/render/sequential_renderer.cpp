#include "render/sequential_renderer.h"

#include "render/row_bands.h"

namespace rt {

RendererInfo SequentialRenderer::info() const { return {RendererKind::sequential, 1, 1, "", std::nullopt, std::nullopt}; }

void SequentialRenderer::render(const CameraFrame& camera) {
  const Extent e = extent();
  renderSpans(camera, [&](const auto& span) { forEachRowBand(e.height, [&](int y) { span(y, 0, e.width); }); });
}

}  // namespace rt
