#include "render/renderer_factory.h"

#include <string>

#include "render/gpu_renderer.h"
#include "render/sequential_renderer.h"
#include "render/simd/simd_renderer.h"
#include "render/tbb_renderer.h"

namespace rt {
namespace {

std::unique_ptr<CPURenderer> makeCpuRenderer(RendererKind kind, const ParallelSettings& settings) {
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
  return nullptr;
}

}  // namespace

std::unique_ptr<Renderer> makeRenderer(RendererKind kind, const ParallelSettings& settings,
                                       const PresentSetup& present) {
  if (kind == RendererKind::gpu) return std::make_unique<GPURenderer>(present);
  if (auto cpu = makeCpuRenderer(kind, settings)) {
    cpu->setPresentSetup(present);
    return cpu;
  }
  throw RendererUnavailable("renderer '" + std::string(nameOf(kind)) + "' is not built in this version");
}

}  // namespace rt
