#include "render/cpu_renderer.h"

#include <algorithm>
#include <stdexcept>

namespace rt {

void CPURenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  scene_ = &scene;
  options_ = options;
  if (frame_.extent() != extent) frame_ = Image(extent);
}

void CPURenderer::present(Image& target) {
  if (target.extent() != frame_.extent()) throw std::logic_error("present: target extent differs from the frame's");
  std::ranges::copy(frame_.pixels(), target.pixels().begin());
}

}  // namespace rt
