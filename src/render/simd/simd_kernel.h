#pragma once
// No Highway types here: the per-target code lives behind packet_kernels.h.
#include <span>
#include <string>
#include <vector>

#include "core/image.h"
#include "render/cpu_contracts.h"
#include "render/renderer.h"
#include "render/simd/packet_kernels.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt {

// Thrown when --lanes asks for more float lanes than the dispatched target
// has: the renderer as asked does not exist on this CPU.
class LanesUnsupported : public RendererUnavailable {
 public:
  using RendererUnavailable::RendererUnavailable;
};

// --precision f16 where the kernel has no half-precision packets: a target
// without native f16 arithmetic, a BVH, or more spheres than an f16 lane
// indexes exactly (docs/render-model.md section 10).
class HalfPrecisionUnsupported : public RendererUnavailable {
 public:
  using RendererUnavailable::RendererUnavailable;
};

// The SIMD kernel (simd_tbb, simd_only; the thesis' SIMDRenderer): packets
// of `lanes` horizontally adjacent pixels traced together in SIMD
// registers, the instruction set chosen per CPU at run time (Highway).
class SimdKernel {
 public:
  static constexpr Kernel kId = Kernel::simd;

  // Picks the kernels of the best target the CPU has (or a test's forced
  // one) once, here, at settings.lanes (float lanes; prepare() switches to
  // f16 lanes for --precision f16). Throws LanesUnsupported or
  // std::invalid_argument.
  explicit SimdKernel(const ParallelSettings& settings = {});

  [[nodiscard]] int lanes() const { return kernels_.lanes; }
  // The type of the prepared kernel's arithmetic (f32 until prepare() says otherwise).
  [[nodiscard]] Precision precision() const { return precision_; }
  [[nodiscard]] std::string simdTarget() const { return simd::targetName(target_.target); }
  // A span starts at a multiple of the packet width.
  [[nodiscard]] int alignment() const { return kernels_.lanes; }
  [[nodiscard]] std::optional<AccelStructureInfo> accelStructure() const;
  // How the kernel walks the BVH (accel bvh only) and traversal hybrid's
  // threshold as resolved; empty where none applies.
  [[nodiscard]] std::optional<Traversal> traversal() const { return traversal_; }
  [[nodiscard]] std::optional<int> hybridThreshold() const;
  // --counters: the last frame's tallies summed over the threads.
  [[nodiscard]] std::optional<LaneCounters> counters() const;

  // The spheres as arrays (and their BVH with --accel bvh), the scene's
  // light and shading, the variant the options select, and two-pass
  // scratch for `slots` worker threads. Throws HalfPrecisionUnsupported or
  // LanesUnsupported where --precision f16 has no kernel.
  void prepare(const Scene& scene, const RenderOptions& options, int slots);
  void beginFrame(const CameraFrame& camera, Image& frame);
  // Pixels x0..x1-1 of row y; `slot` (the worker's index) picks its scratch.
  void renderSpan(int slot, int y, int x0, int x1) {
    kernel_(params_, y, x0, x1, scratchOf(slot), counting() ? &counters_[static_cast<std::size_t>(slot)] : nullptr);
  }

  // Traversal hybrid's threshold without --hybrid-threshold, for `lanes`-wide packets.
  static int defaultHybridThreshold(int lanes);

 private:
  // A cache line: scratch slots are whole lines, so two threads never write
  // to one line, and every packet store is aligned.
  struct alignas(64) CacheLine {
    float floats[16];
  };

  [[nodiscard]] simd::LaneKernels kernelsFor(const Scene& scene, const RenderOptions& options) const;
  void prepareSpheres(const Scene& scene);
  void prepareHalfSpheres();
  void prepareScratch(int maxDepth, int slots);
  [[nodiscard]] std::span<float> scratchOf(int slot);

  simd::TargetKernels target_;
  int lanesAsked_;                     // settings.lanes
  simd::LaneKernels floatKernels_;     // at lanesAsked_
  simd::LaneKernels kernels_;          // the prepared precision's: floatKernels_ or f16 ones
  simd::SpanKernel kernel_ = nullptr;  // the variant the options select
  Precision precision_ = Precision::f32;
  simd::FrameParams params_{};  // scene parts set in prepare(), camera per frame

  std::vector<float> sphereData_;               // SoA: 8 arrays of sphereCount floats each
  std::vector<hwy::float16_t> halfSphereData_;  // --precision f16: the same, rounded to f16
  AccelStructure accel_;
  std::optional<WideBvh> wide_;         // --traversal single or hybrid
  std::optional<Traversal> traversal_;  // with accel bvh
  std::vector<LaneCounters> counters_;  // --counters: one tally per thread slot; empty without
  [[nodiscard]] bool counting() const { return !counters_.empty(); }
  std::vector<CacheLine> scratch_;  // one slot per thread for the two-pass forward pass
  std::size_t scratchLinesPerSlot_ = 0;
};
static_assert(CpuKernel<SimdKernel>);

}  // namespace rt
