#pragma once
#include "render/cpu_renderer.h"
#include "render/scalar_kernel.h"

namespace rt {

// The reference for correctness and speedup: the scalar kernel, one thread.
class SequentialRenderer final : public CPURenderer {
 public:
  [[nodiscard]] RendererInfo info() const override;
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  void render(const CameraFrame& camera) override;

 private:
  kernel::ShadingInputs<float> inputs_{};
};

}  // namespace rt
