#pragma once
#include "render/row_scheduler.h"
#include "render/scalar_cpu_renderer.h"

namespace rt {

// The thesis' "TBB only" ablation: the sequential renderer's scalar kernel,
// rows spread over oneTBB threads.
class TBBRenderer final : public ScalarCPURenderer {
 public:
  // Throws std::invalid_argument for settings the scheduler rejects.
  explicit TBBRenderer(const ParallelSettings& settings);

  [[nodiscard]] RendererInfo info() const override;
  void render(const CameraFrame& camera) override;

 private:
  RowScheduler scheduler_;
};

}  // namespace rt
