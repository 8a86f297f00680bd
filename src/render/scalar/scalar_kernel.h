#pragma once
#include <string>

#include "core/image.h"
#include "render/accel/bvh.h"
#include "render/cpu_contracts.h"
#include "render/render_options.h"
#include "render/scalar/scalar_model.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt {

// The scalar kernel (sequential, tbb_only): one pixel at a time in float,
// the same code as the double-precision reference. A scheduler calls
// renderSpan() for the spans of the frame that beginFrame() set up.
class ScalarKernel {
 public:
  static constexpr Kernel kId = Kernel::scalar;

  ScalarKernel() = default;
  explicit ScalarKernel(const ParallelSettings& /*settings*/) {}

  [[nodiscard]] int lanes() const { return 1; }
  [[nodiscard]] std::string simdTarget() const { return {}; }
  // A span may start at any pixel.
  [[nodiscard]] int alignment() const { return 1; }
  [[nodiscard]] std::optional<AccelStructureInfo> accelStructure() const { return accel_.info(); }

  // Converts the scene's inputs, builds the BVH with --accel bvh, and picks
  // the variant the options select; `slots` (worker threads) needs no scratch.
  void prepare(const Scene& scene, const RenderOptions& options, int slots);
  // Per frame: the camera and the image the spans are written into.
  void beginFrame(const CameraFrame& camera, Image& frame) {
    camera_ = camera;
    frame_ = &frame;
  }
  // Pixels x0..x1-1 of row y; `slot` is the calling worker's index.
  void renderSpan(int /*slot*/, int y, int x0, int x1) const {
    span_(inputs_, camera_, frame_->extent(), y, x0, x1, frame_->row(y));
  }

 private:
  using SpanFunction = void (*)(const kernel::ShadingInputs<float>&, const CameraFrame&, Extent, int y, int x0, int x1,
                                std::span<Rgba8> row);

  kernel::ShadingInputs<float> inputs_{};
  AccelStructure accel_;
  SpanFunction span_ = nullptr;
  CameraFrame camera_{};
  Image* frame_ = nullptr;
};
static_assert(CpuKernel<ScalarKernel>);

}  // namespace rt
