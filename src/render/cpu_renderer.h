#pragma once
#include <memory>

#include "render/present_setup.h"
#include "render/renderer.h"

namespace rt {

namespace gpu {
class FrameUpload;
}

// The CPU renderers render into a working buffer in RAM, which Present then
// hands on (the thesis' StagingData, copied to the swapchain image).
class CPURenderer : public Renderer {
 public:
  CPURenderer();
  ~CPURenderer() override;

  // Before prepare(): where Present puts the frames (default: nowhere, `none`).
  void setPresentSetup(PresentSetup setup);
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  void present() override;
  void readPresented(Image& target) override;

 protected:
  [[nodiscard]] const Scene& scene() const { return *scene_; }
  [[nodiscard]] const RenderOptions& options() const { return options_; }
  [[nodiscard]] Extent extent() const { return frame_.extent(); }
  [[nodiscard]] Image& workingBuffer() { return frame_; }

 private:
  const Scene* scene_ = nullptr;
  RenderOptions options_;
  Image frame_;
  PresentSetup presentSetup_;
  std::unique_ptr<gpu::FrameUpload> upload_;  // mode upload only
};

}  // namespace rt
