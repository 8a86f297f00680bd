#pragma once
#include <memory>
#include <optional>

#include "gpu/present/device_renderer.h"

namespace rt::gpu {

// The GPU's reference renderer (gpu_rt): what a user of a Vulkan GPU would
// pick instead of our compute BVH, the driver's own acceleration structure
// traced through VK_KHR_ray_tracing_pipeline (docs/render-model.md section 3,
// "The ray-tracing pipeline renderer"). The render model is the compute
// renderer's, in the same GLSL; the driver finds the nearest sphere, whose
// float test is our intersection shader. Needs a device opened with
// ContextOptions::rayTracing. Vulkan stays out of this header.
class GpuRtRenderer final : public DeviceRenderer {
 public:
  // As GPURenderer's: `present` picks the Present path, `window` the
  // swapchain of mode window. Throws std::invalid_argument without a device.
  GpuRtRenderer(std::shared_ptr<Context> device, PresentMode present, std::shared_ptr<Swapchain> window = nullptr);
  ~GpuRtRenderer() override;

  [[nodiscard]] RendererInfo info() const override;
  // Builds the acceleration structures (their build time and memory go
  // into info()), the pipeline variant and its binding table, uploads the
  // spheres, sizes the images.
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  // Records, submits and waits for one trace of the frame; GPU timestamps around it.
  void render(const CameraFrame& camera) override;

 private:
  struct SceneObjects;
  SceneObjects& prepared();  // throws std::logic_error before prepare()
  ShaderOutput& output() override;

  std::unique_ptr<SceneObjects> scene_;
};

}  // namespace rt::gpu
