#pragma once
#include <stdexcept>
#include <string>
#include <string_view>

#include "rt_schema.h"

namespace rt {

using schema::Accel;
using schema::Algorithm;
using schema::BoxPadding;
using schema::EarlyExit;
using schema::GpuBvh;
using schema::GpuPath;
using schema::GpuRtReorder;
using schema::GpuSchedule;
using schema::Kernel;
using schema::Partition;
using schema::Precision;
using schema::PresentMode;
using schema::RendererKind;
using schema::RendererOption;
using schema::Scheduler;
using schema::Stage;
using schema::Traversal;

// A set of early exits (docs/render-model.md section 6) as a bit mask over EarlyExit.
class EarlyExitSet {
 public:
  constexpr EarlyExitSet() = default;
  constexpr explicit EarlyExitSet(unsigned mask) : mask_(mask) {}
  static constexpr EarlyExitSet all() { return EarlyExitSet((1u << schema::kEarlyExitNames.size()) - 1u); }

  [[nodiscard]] constexpr bool has(EarlyExit e) const { return (mask_ >> static_cast<int>(e)) & 1u; }
  constexpr void add(EarlyExit e) { mask_ |= 1u << static_cast<int>(e); }
  [[nodiscard]] constexpr unsigned mask() const { return mask_; }
  friend constexpr bool operator==(EarlyExitSet, EarlyExitSet) = default;

  // "none" or the names joined by '+', in schema order ("bounce+sphere").
  [[nodiscard]] std::string toString() const;

 private:
  unsigned mask_ = 0;
};

struct RenderOptions {
  Algorithm algorithm = Algorithm::single_pass;
  EarlyExitSet earlyExits = EarlyExitSet::all();
  // How a ray finds its nearest sphere; never changes the image.
  Accel accel = Accel::none;
  // How the SIMD kernel walks the BVH (accel bvh only); never changes the image.
  Traversal traversal = Traversal::packet;
  // Traversal hybrid: a packet goes on as single rays where at most this
  // many of its lanes reach a node; kDefaultHybridThreshold: the kernel's
  // measured default for its packet width.
  static constexpr int kDefaultHybridThreshold = 0;
  int hybridThreshold = kDefaultHybridThreshold;
  // The GPU renderer's walk (docs/render-model.md section 3, "How the GPU
  // renderer walks the BVH"), with accel bvh only; never changes the image.
  GpuBvh gpuBvh = GpuBvh::binary;
  // The gpu_rt renderer: reorder invocations by hit before shading
  // (VK_NV_ray_tracing_invocation_reorder); never changes the image.
  GpuRtReorder gpuRtReorder = GpuRtReorder::none;
  // The floating-point type of the render model's arithmetic: f16 is the
  // thesis' half-precision experiment (docs/render-model.md section 10),
  // which changes the image; the SIMD renderers and the GPU renderer only.
  Precision precision = Precision::f32;
  // --counters: the SIMD kernel (and the GPU renderer) tallies rays, node visits, sphere tests and
  // lane occupancy per frame (LaneCounters); off, the kernel compiled without them runs.
  bool counters = false;
};

RenderOptions optionsForStage(Stage stage);

// How the parallel CPU renderers run: --threads, --lanes, --grain, --partition.
struct ParallelSettings {
  static constexpr int kAllCores = 0;
  static constexpr int kNativeLanes = 0;
  int threads = kAllCores;   // oneTBB worker threads, the calling one included
  int lanes = kNativeLanes;  // pixels per SIMD packet; native = widest vector of the dispatched target
  int grain = 1;             // oneTBB grain size in rows (blocked_range grainsize)
  Partition partition = Partition::rows;
};

// The schema's row for a renderer: its flag, (kernel, scheduler) pair and options.
constexpr const schema::RendererDefinition& definitionOf(RendererKind kind) {
  return schema::kRendererDefinitions[static_cast<std::size_t>(kind)];
}

// The CPU renderer that pairs `kernel` with `scheduler`, as the schema names it.
constexpr RendererKind rendererFor(Kernel kernel, Scheduler scheduler) {
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    const auto& d = schema::kRendererDefinitions[i];
    if (d.kernel == kernel && d.scheduler == scheduler) return static_cast<RendererKind>(i);
  }
  throw std::logic_error("no renderer in the schema pairs this kernel with this scheduler");
}

// nameOf(enum value): the schema name, generated with each enum.
using schema::nameOf;

}  // namespace rt
