#pragma once
// No Highway types here: the SIMD code lives behind simd_kernel.h.
#include <optional>
#include <vector>

#include "render/cpu_renderer.h"
#include "render/renderer_factory.h"
#include "render/row_scheduler.h"
#include "render/simd/simd_kernel.h"

namespace rt {

// Thrown when --lanes asks for more float lanes than the dispatched target
// has: the renderer as asked does not exist on this CPU.
class LanesUnsupported : public RendererUnavailable {
 public:
  using RendererUnavailable::RendererUnavailable;
};

// The thesis' SIMDRenderer: packets of `lanes` horizontally adjacent pixels
// traced together in SIMD registers, chosen per CPU at run time (Highway).
// Threaded (simd_tbb: rows over oneTBB) or on the calling thread alone
// (simd_only).
class SIMDRenderer final : public CPURenderer {
 public:
  enum class Threading { tbb, single };

  // Picks the kernel of the best target the CPU has (or a test's forced
  // one) once, here. Throws LanesUnsupported or std::invalid_argument.
  SIMDRenderer(Threading threading, const ParallelSettings& settings);

  [[nodiscard]] RendererInfo info() const override;
  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override;
  void render(const CameraFrame& camera) override;

 private:
  // A cache line: scratch slots are whole lines, so two threads never write
  // to one line, and every packet store is aligned.
  struct alignas(64) CacheLine {
    float floats[16];
  };

  void prepareSpheres(const Scene& scene);
  void prepareScratch(int maxDepth);
  [[nodiscard]] simd::FrameParams frameParams(const CameraFrame& camera);
  [[nodiscard]] std::span<float> scratchOf(int slot);

  simd::TargetKernels target_;
  simd::LaneKernels kernels_;
  std::optional<RowScheduler> scheduler_;  // empty for simd_only
  simd::SpanKernel kernel_ = nullptr;      // the variant the options select

  std::vector<float> sphereData_;  // SoA: 8 arrays of sphereCount floats each
  simd::SphereArrays spheres_;
  std::vector<CacheLine> scratch_;  // one slot per thread for the two-pass forward pass
  std::size_t scratchLinesPerSlot_ = 0;
};

}  // namespace rt
