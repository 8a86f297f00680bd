#pragma once
#include "render/scalar_cpu_renderer.h"

namespace rt {

// The reference for correctness and speedup: the scalar kernel, one thread.
class SequentialRenderer final : public ScalarCPURenderer {
 public:
  [[nodiscard]] RendererInfo info() const override;
  void render(const CameraFrame& camera) override;
};

}  // namespace rt
