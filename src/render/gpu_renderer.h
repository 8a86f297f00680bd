#pragma once
#include <memory>
#include <optional>

#include "render/present_setup.h"
#include "render/renderer.h"

namespace rt {

// The thesis' GPURenderer: a Vulkan compute shader, one invocation per
// pixel, on any Vulkan 1.2 device (a GPU, or lavapipe on the CPU).
// Spheres live in a storage buffer, camera, light and sizes go as push
// constants every frame, the shader writes an rgba8 storage image, and
// Present copies that into the present image. Vulkan stays out of this
// header: the objects live in src/render/gpu_renderer.cpp.
class GPURenderer final : public Renderer {
 public:
  // `setup.device` is required; setup.mode picks the Present path.
  explicit GPURenderer(PresentSetup setup);
  ~GPURenderer() override;

  [[nodiscard]] RendererInfo info() const override;
  // Builds the pipeline variant (algorithm and bounce exit are
  // specialization constants), uploads the spheres, sizes the images.
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  // Records, submits and waits for the dispatch; GPU timestamps around it.
  void render(const CameraFrame& camera) override;
  void present() override;
  void readPresented(Image& target) override;
  [[nodiscard]] std::optional<double> lastGpuMs() const override { return gpuMs_; }

 private:
  struct DeviceObjects;
  struct SceneObjects;
  SceneObjects& prepared();  // throws std::logic_error before prepare()

  PresentSetup setup_;  // holds the device: declared first, so destroyed last
  std::unique_ptr<DeviceObjects> device_;
  std::unique_ptr<SceneObjects> scene_;
  std::optional<double> gpuMs_;
};

}  // namespace rt
