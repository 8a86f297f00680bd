#include "render/renderer_factory.h"

#include <string>

#include "render/sequential_renderer.h"
#include "render/simd/simd_renderer.h"
#include "render/tbb_renderer.h"

namespace rt {

std::unique_ptr<Renderer> makeRenderer(RendererKind kind, const ParallelSettings& settings) {
  switch (kind) {
    case RendererKind::sequential:
      return std::make_unique<SequentialRenderer>();
    case RendererKind::simd_tbb:
      return std::make_unique<SIMDRenderer>(SIMDRenderer::Threading::tbb, settings);
    case RendererKind::simd_only:
      return std::make_unique<SIMDRenderer>(SIMDRenderer::Threading::single, settings);
    case RendererKind::tbb_only:
      return std::make_unique<TBBRenderer>(settings);
    case RendererKind::gpu:
      break;
  }
  throw RendererUnavailable("renderer '" + std::string(nameOf(kind)) +
                            "' is not built yet in this version; available: sequential, simd_tbb, simd_only, tbb_only");
}

}  // namespace rt
