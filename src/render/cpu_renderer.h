#pragma once
#include "render/renderer.h"

namespace rt {

// The CPU renderers render into a working buffer in RAM, which Present then
// hands on (the thesis' StagingData, copied to the swapchain image).
class CPURenderer : public Renderer {
 public:
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  void present(Image& target) override;

 protected:
  [[nodiscard]] const Scene& scene() const { return *scene_; }
  [[nodiscard]] const RenderOptions& options() const { return options_; }
  [[nodiscard]] Extent extent() const { return frame_.extent(); }
  [[nodiscard]] Image& workingBuffer() { return frame_; }

 private:
  const Scene* scene_ = nullptr;
  RenderOptions options_;
  Image frame_;
};

}  // namespace rt
