#pragma once
#include <memory>
#include <optional>

#include "gpu/present/device_renderer.h"

namespace rt {
class AccelStructure;
}

namespace rt::gpu {

// The thesis' GPURenderer: a Vulkan compute shader, one invocation per
// pixel, on any Vulkan 1.2 device (a GPU, or lavapipe on the CPU); its
// BVH, schedule and path are the variants of RenderOptions' gpu axes.
// Spheres live in a storage buffer, camera, light and sizes go as push
// constants every frame, the shader writes an rgba8 storage image, and
// Present copies that into the present image. Vulkan stays out of this
// header: the objects live in gpu_renderer.cpp.
class GPURenderer final : public DeviceRenderer {
 public:
  // `device` is required; `present` picks the Present path: `upload`
  // copies each frame into the present image, `none` leaves it in the
  // storage image, `window` blits it into an image of `window`'s swapchain
  // and presents that. Throws std::invalid_argument without a device, or
  // for `window` without a swapchain.
  GPURenderer(std::shared_ptr<Context> device, PresentMode present, std::shared_ptr<Swapchain> window = nullptr);
  ~GPURenderer() override;  // with a window: waits for the frames in flight, which read the storage image

  [[nodiscard]] RendererInfo info() const override;
  // Builds the pipeline variant (algorithm, bounce exit and --accel are
  // specialization constants), uploads the spheres (and with --accel bvh
  // builds and uploads their BVH), sizes the images.
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  // Records, submits and waits for the dispatch; GPU timestamps around it.
  void render(const CameraFrame& camera) override;
  // --counters: the shader's tallies of the last frame (all its dispatches).
  [[nodiscard]] std::optional<LaneCounters> lastCounters() const override { return counters_; }

 private:
  struct SceneObjects;
  SceneObjects& prepared();  // throws std::logic_error before prepare()
  ShaderOutput& output() override;
  std::unique_ptr<SceneObjects> prepareVariant(const Scene& scene, Extent extent, const RenderOptions& options,
                                               AccelStructure accel);
  std::unique_ptr<SceneObjects> prepareFastestWalk(const Scene& scene, Extent extent, const RenderOptions& options);
  double probeGpuMs(SceneObjects& objects, const CameraFrame& camera);
  std::optional<double> renderWith(SceneObjects& s, const CameraFrame& camera);

  std::unique_ptr<SceneObjects> scene_;
  std::optional<LaneCounters> counters_;
  std::optional<GpuWalkProbe> walkProbe_;  // --gpu-bvh auto only
};

}  // namespace rt::gpu
