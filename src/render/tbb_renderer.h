#pragma once
#include "render/cpu_renderer.h"
#include "render/row_scheduler.h"
#include "render/scalar_kernel.h"

namespace rt {

// The thesis' "TBB only" ablation: the sequential renderer's scalar kernel,
// rows spread over oneTBB threads.
class TBBRenderer final : public CPURenderer {
 public:
  // Throws std::invalid_argument for settings the scheduler rejects.
  explicit TBBRenderer(const ParallelSettings& settings);

  [[nodiscard]] RendererInfo info() const override;
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  void render(const CameraFrame& camera) override;

 private:
  RowScheduler scheduler_;
  kernel::ShadingInputs<float> inputs_{};
};

}  // namespace rt
