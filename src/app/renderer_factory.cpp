#include "app/renderer_factory.h"

#include <stdexcept>

#include "gpu/compute/gpu_renderer.h"
#include "gpu/present/frame_upload.h"
#include "gpu/present/swapchain_upload.h"
#include "gpu/raytracing/gpu_rt_renderer.h"
#include "render/cpu_renderers.h"

namespace rt {

std::unique_ptr<Renderer> makeRenderer(RendererKind kind, const ParallelSettings& settings,
                                       const PresentSetup& present) {
  if (kind == RendererKind::gpu) {
    return std::make_unique<gpu::GPURenderer>(present.device, present.mode, present.swapchain);
  }
  if (kind == RendererKind::gpu_rt) {
    return std::make_unique<gpu::GpuRtRenderer>(present.device, present.mode, present.swapchain);
  }
  std::unique_ptr<FrameSink> sink;
  if (present.mode == PresentMode::upload) {
    if (!present.device) throw std::invalid_argument("present mode 'upload' needs a Vulkan device");
    sink = gpu::makeFrameUpload(present.device);
  } else if (present.mode == PresentMode::window) {
    sink = gpu::makeSwapchainUpload(present.swapchain);
  }
  return makeCpuRenderer(kind, settings, std::move(sink));
}

}  // namespace rt
