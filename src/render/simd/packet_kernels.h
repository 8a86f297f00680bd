#pragma once
// The plain interface of the packet kernels: no Highway types, so the SIMD
// kernel class and the tests include it without compiling per target. The
// kernels themselves (packet_kernel-inl.h) are compiled once per Highway
// target in packet_kernels.cc and reached through one dynamic dispatch per
// renderer.
#include <hwy/base.h>  // hwy::float16_t, the f16 kernel's storage type (no vector types)

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"
#include "render/accel/bvh.h"
#include "render/accel/wide_bvh.h"
#include "render/kernel_variant.h"
#include "render/lane_counters.h"
#include "render/shading_params.h"
#include "scene/camera.h"

namespace rt::simd {

// The scene's spheres as structure of arrays: one contiguous array per
// component, so a packet loads one sphere's component with one broadcast.
// T is the packets' lane type: float, or hwy::float16_t for the half-
// precision kernel (docs/render-model.md section 10).
template <class T>
struct SphereData {
  const T* centerX = nullptr;
  const T* centerY = nullptr;
  const T* centerZ = nullptr;
  const T* radius = nullptr;
  const T* radiusSquared = nullptr;  // radius * radius in float, as the scalar kernel computes it
  const T* colorR = nullptr;
  const T* colorG = nullptr;
  const T* colorB = nullptr;
  int count = 0;
};

struct SphereArrays : SphereData<float> {
  const Bvh* bvh = nullptr;       // --accel bvh; null: brute force
  const WideBvh* wide = nullptr;  // --traversal single or hybrid; null otherwise
};

// Everything one frame's kernel calls read: the scene's parts set once per
// scene in prepare(), the camera and the target per frame.
struct FrameParams {
  SphereArrays spheres;
  SphereData<hwy::float16_t> halfSpheres;  // --precision f16: the same spheres rounded to f16 once
  ShadingParams shading;
  CameraFrame camera;
  Extent extent;
  Rgba8* pixels;  // the working buffer, row-major, extent.width pixels per row
  // --traversal hybrid: a packet goes on as single rays where at most this
  // many of its lanes reach a node.
  int hybridThreshold;
};

// Renders pixels x0..x1-1 of row y; x0 is a multiple of the packet width.
// `scratch` holds the two-pass forward pass' packets (scratchFloats() floats,
// 64-byte aligned); the single-pass variants do not touch it. `counters`:
// the calling thread's tally, which the counting variants add to (the
// others ignore it; it may be null for them).
using SpanKernel = void (*)(const FrameParams& frame, int y, int x0, int x1, std::span<float> scratch,
                            LaneCounters* counters);

// Per packet width: the kernel's variants, or none where the target
// cannot hold that many float lanes.
struct LaneKernels {
  int lanes = 0;
  SpanKernel variants[KernelVariant::kCount] = {};  // by KernelVariant::index()
};

// A target's kernels for one lane type: the native width and each of the
// schema's lane widths.
struct LaneSet {
  int nativeLanes = 0;  // lanes of the widest vector; 0: this lane type has no kernels here
  LaneKernels native;   // --lanes native
  // --lanes N for each N of schema::kLaneWidths, in that order (lanes 0
  // where the target cannot hold N lanes).
  std::array<LaneKernels, schema::kLaneWidths.size()> capped;
};

// What the dispatched target offers. Taken once per renderer, so the target
// recorded in the CSV is the one whose code renders, even if a test forces
// another target later.
struct TargetKernels {
  std::int64_t target = 0;  // a HWY_* bit
  LaneSet f32;              // every variant
  // --precision f16: brute force only, and only where Highway (1.2 and
  // newer) gives this target native f16 arithmetic; empty elsewhere.
  LaneSet f16;
};

// The f16 kernel keeps a sphere's index in an f16 lane, exact up to 2^11.
inline constexpr int kHalfPrecisionMaxSpheres = 2048;

// Vectors stored per two-pass segment: ray origin and direction, hit
// position, normal, distance, sphere colour and the hit mask.
inline constexpr std::size_t kSegmentVectors = 17;

// Floats of two-pass scratch a thread needs for `lanes`-wide packets and
// `maxDepth` stored segments (f16 packets fill half of it).
inline std::size_t scratchFloats(int lanes, int maxDepth) {
  return kSegmentVectors * static_cast<std::size_t>(lanes) * static_cast<std::size_t>(maxDepth);
}

// The kernels of the best target the CPU supports (or the one a test forced).
TargetKernels dispatchedKernels();

// The counting half of them (packet_kernels_counted.cc), which dispatchedKernels() merges in.
TargetKernels dispatchedCountedKernels();

// Highway's name of a target bit ("AVX3", "SSE4", ...).
std::string targetName(std::int64_t target);

// The Highway version this build was compiled with ("1.2.0").
std::string highwayVersion();

// Targets compiled into the kernel that this CPU can run, best first.
std::vector<std::int64_t> availableTargets();

// A Highway target the packet kernels were compiled for.
struct CompiledTarget {
  std::int64_t target = 0;  // a HWY_* bit
  bool nativeF16 = false;   // whether its kernels include the f16 lanes (docs/render-model.md section 10)
};

// Every target this build compiled the packet kernels for, best first,
// whether or not this CPU runs it: what the build holds, recorded by each
// target's own compile, not what dispatch picks.
std::vector<CompiledTarget> compiledTargets();

// Targets with native f16 arithmetic that this CPU runs but this build left
// out (RT_SIMD_FEWER_TARGETS, the debug preset's): empty where the build has
// every such target, and always before Highway 1.2.
std::vector<std::int64_t> halfPrecisionTargetsLeftOut();

// Called once by each target's compile of packet_kernels.cc (a static
// initializer there), which is how compiledTargets() learns the list.
bool listCompiledTarget(CompiledTarget target);

// For tests: makes dispatch pick `target` while alive, then lifts the mock.
class ScopedTargetOverride {
 public:
  explicit ScopedTargetOverride(std::int64_t target);
  ~ScopedTargetOverride();
  ScopedTargetOverride(const ScopedTargetOverride&) = delete;
  ScopedTargetOverride& operator=(const ScopedTargetOverride&) = delete;
};

}  // namespace rt::simd
