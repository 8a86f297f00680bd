#include "render/renderer_factory.h"

#include <string>

#include "render/sequential_renderer.h"

namespace rt {

std::unique_ptr<Renderer> makeRenderer(RendererKind kind) {
  switch (kind) {
    case RendererKind::sequential:
      return std::make_unique<SequentialRenderer>();
    case RendererKind::simd_tbb:
    case RendererKind::simd_only:
    case RendererKind::tbb_only:
    case RendererKind::gpu:
      break;
  }
  throw RendererUnavailable("renderer '" + std::string(nameOf(kind)) +
                            "' is not built yet in this version; available: sequential");
}

}  // namespace rt
