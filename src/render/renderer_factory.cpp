#include "render/renderer_factory.h"

#include <string>

#include "render/gpu_renderer.h"
#include "render/sequential_renderer.h"

namespace rt {
namespace {

std::unique_ptr<CPURenderer> makeCpuRenderer(RendererKind kind) {
  switch (kind) {
    case RendererKind::sequential:
      return std::make_unique<SequentialRenderer>();
    case RendererKind::simd_tbb:
    case RendererKind::simd_only:
    case RendererKind::tbb_only:
    case RendererKind::gpu:
      break;
  }
  return nullptr;
}

}  // namespace

std::unique_ptr<Renderer> makeRenderer(RendererKind kind, const PresentSetup& present) {
  if (kind == RendererKind::gpu) return std::make_unique<GPURenderer>(present);
  if (auto cpu = makeCpuRenderer(kind)) {
    cpu->setPresentSetup(present);
    return cpu;
  }
  throw RendererUnavailable("renderer '" + std::string(nameOf(kind)) +
                            "' is not built yet in this version; available: sequential, gpu");
}

}  // namespace rt
