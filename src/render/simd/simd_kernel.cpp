#include "render/simd/simd_kernel.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <string_view>

#include "render/kernel_variant.h"

namespace rt {
namespace {

// --lanes: native, or exactly one of the schema's lane widths if the target has it.
simd::LaneKernels selectLanes(const simd::LaneSet& set, const std::string& target, std::string_view laneType,
                              int lanes) {
  if (lanes == ParallelSettings::kNativeLanes) return set.native;
  const auto* it = std::ranges::find(schema::kLaneWidths, lanes);
  if (it == schema::kLaneWidths.end()) {
    throw std::invalid_argument("lanes " + std::to_string(lanes) + " is not one of the schema's lane widths");
  }
  const simd::LaneKernels& kernels = set.capped[static_cast<std::size_t>(it - schema::kLaneWidths.begin())];
  if (kernels.lanes != lanes) {
    throw LanesUnsupported("--lanes " + std::to_string(lanes) + ": the CPU's SIMD target " + target + " has at most " +
                           std::to_string(set.nativeLanes) + " " + std::string(laneType) + " lanes");
  }
  return kernels;
}

// Why --precision f16 has no kernel on this target: Highway computes in f16
// natively only from version 1.2 on, and only on the targets named
// (docs/render-model.md section 10).
std::string halfPrecisionRefusal(const std::string& target) {
  std::string refusal =
      "the SIMD renderers cannot compute in half precision (--precision f16) here: this CPU's Highway target " +
      target + " has no native f16 arithmetic (Highway " + simd::highwayVersion() + ").";
  for (const std::int64_t leftOut : simd::halfPrecisionTargetsLeftOut()) {
    refusal += " This CPU runs " + simd::targetName(leftOut) +
               ", which computes in f16, but this build left that target out (RT_SIMD_FEWER_TARGETS, as the debug "
               "preset builds): the release preset has it (cmake --preset release, or scripts/raytracer).";
  }
  return refusal +
         " An f16 kernel is compiled for the targets that have it from Highway 1.2 on: AVX3_SPR (AVX512-FP16, "
         "Intel Xeon from Sapphire Rapids on, with GCC), NEON_BF16 (Arm CPUs with BF16), and NEON where the build "
         "enables the ARMv8.2-A FP16 extension, SVE and SVE2. "
         "--gpu --precision f16 runs the experiment where the Vulkan device offers shaderFloat16";
}

}  // namespace

SimdKernel::SimdKernel(const ParallelSettings& settings)
    : target_(simd::dispatchedKernels()),
      lanesAsked_(settings.lanes),
      floatKernels_(selectLanes(target_.f32, simdTarget(), "float", settings.lanes)),
      kernels_(floatKernels_) {}

// The float kernels, or for --precision f16 the f16 ones where they exist:
// brute force over at most kHalfPrecisionMaxSpheres spheres on a target with
// native f16 arithmetic (docs/render-model.md section 10). The scene's and
// the options' limits come first, so they are refused the same on every CPU.
simd::LaneKernels SimdKernel::kernelsFor(const Scene& scene, const RenderOptions& options) const {
  if (options.precision == Precision::f32) return floatKernels_;
  if (options.accel != Accel::none) {
    throw HalfPrecisionUnsupported(
        "the SIMD renderers' half-precision kernel (--precision f16) is brute force only: use --accel none");
  }
  if (scene.spheres.size() > static_cast<std::size_t>(simd::kHalfPrecisionMaxSpheres)) {
    throw HalfPrecisionUnsupported("the SIMD renderers' half-precision kernel (--precision f16) takes at most " +
                                   std::to_string(simd::kHalfPrecisionMaxSpheres) +
                                   " spheres (an f16 lane holds their indices exactly up to there); the scene has " +
                                   std::to_string(scene.spheres.size()));
  }
  if (target_.f16.nativeLanes == 0) throw HalfPrecisionUnsupported(halfPrecisionRefusal(simdTarget()));
  return selectLanes(target_.f16, simdTarget(), "f16", lanesAsked_);
}

void SimdKernel::prepare(const Scene& scene, const RenderOptions& asked, int slots) {
  if (asked.hybridThreshold < 0) throw std::invalid_argument("hybrid threshold must not be negative");
  kernels_ = kernelsFor(scene, asked);
  RenderOptions options = asked;
  precision_ = options.precision;
  prepareSpheres(scene);
  if (options.precision == Precision::f16) prepareHalfSpheres();
  options.accel = accel_.prepare(scene.spheres, asked.accel);
  params_.spheres.bvh = accel_.bvh();
  traversal_.reset();
  wide_.reset();
  if (accel_.bvh() != nullptr) {
    traversal_ = options.traversal;
    if (options.traversal != Traversal::packet) wide_ = buildWideBvh(*accel_.bvh(), scene.spheres);
  }
  params_.spheres.wide = wide_ ? &*wide_ : nullptr;
  params_.hybridThreshold = options.hybridThreshold == RenderOptions::kDefaultHybridThreshold
                                ? defaultHybridThreshold(kernels_.lanes)
                                : options.hybridThreshold;
  prepareScratch(scene.render.maxDepth, slots);
  counters_.assign(options.counters ? static_cast<std::size_t>(std::max(slots, 1)) : 0u, LaneCounters{});
  params_.shading = shadingParamsOf(scene);
  kernel_ = kernels_.variants[KernelVariant::of(options).index()];
}

// Measured (docs/experiments/cpu-traversal.md): a packet pays off only while
// nearly all of its lanes reach a node, as for primary rays; split it
// once an eighth of them (at least one) has dropped out.
int SimdKernel::defaultHybridThreshold(int lanes) { return lanes - std::max(1, lanes / 8); }

std::optional<AccelStructureInfo> SimdKernel::accelStructure() const {
  std::optional<AccelStructureInfo> info = accel_.info();
  if (info && wide_) {  // the tree the rays walk is the wide one, built from the binary one
    info->buildMs += wide_->buildMs;
    info->nodes = wide_->nodes.size();
    info->depth = wide_->depth;
  }
  return info;
}

std::optional<int> SimdKernel::hybridThreshold() const {
  if (traversal_ != Traversal::hybrid) return std::nullopt;
  return params_.hybridThreshold;
}

std::optional<LaneCounters> SimdKernel::counters() const {
  if (!counting()) return std::nullopt;
  LaneCounters sum;
  for (const LaneCounters& c : counters_) sum += c;
  return sum;
}

// The spheres as eight contiguous arrays, converted once, not per frame.
void SimdKernel::prepareSpheres(const Scene& scene) {
  const std::size_t n = scene.spheres.size();
  sphereData_.assign(8 * n, 0.0f);
  float* base = sphereData_.data();
  const auto array = [&](int k) { return base + static_cast<std::size_t>(k) * n; };
  for (std::size_t i = 0; i < n; ++i) {
    const Sphere& s = scene.spheres[i];
    array(0)[i] = s.position.x;
    array(1)[i] = s.position.y;
    array(2)[i] = s.position.z;
    array(3)[i] = s.radius;
    array(4)[i] = s.radius * s.radius;
    array(5)[i] = s.color.x;
    array(6)[i] = s.color.y;
    array(7)[i] = s.color.z;
  }
  params_.spheres = {
      {array(0), array(1), array(2), array(3), array(4), array(5), array(6), array(7), static_cast<int>(n)}};
}

// The eight arrays rounded to f16 once. The conversion is Highway 1.2's;
// with an older Highway no target has f16 kernels, and kernelsFor() has
// refused before this is reached.
void SimdKernel::prepareHalfSpheres() {
#if defined(HWY_MAJOR) && (HWY_MAJOR > 1 || HWY_MINOR >= 2)
  halfSphereData_.resize(sphereData_.size());
  std::ranges::transform(sphereData_, halfSphereData_.begin(), [](float v) { return hwy::F16FromF32(v); });
  const std::size_t n = sphereData_.size() / 8;
  const auto array = [&](int k) { return halfSphereData_.data() + static_cast<std::size_t>(k) * n; };
  params_.halfSpheres = {array(0), array(1), array(2), array(3),           array(4),
                         array(5), array(6), array(7), static_cast<int>(n)};
#endif
}

void SimdKernel::prepareScratch(int maxDepth, int slots) {
  constexpr std::size_t kFloatsPerLine = sizeof(CacheLine) / sizeof(float);
  const std::size_t floats = simd::scratchFloats(kernels_.lanes, maxDepth);
  scratchLinesPerSlot_ = (floats + kFloatsPerLine - 1) / kFloatsPerLine;
  scratch_.assign(static_cast<std::size_t>(std::max(slots, 1)) * scratchLinesPerSlot_, CacheLine{});
}

std::span<float> SimdKernel::scratchOf(int slot) {
  CacheLine* first = scratch_.data() + static_cast<std::size_t>(slot) * scratchLinesPerSlot_;
  return {first->floats, scratchLinesPerSlot_ * (sizeof(CacheLine) / sizeof(float))};
}

void SimdKernel::beginFrame(const CameraFrame& camera, Image& frame) {
  params_.camera = camera;
  params_.extent = frame.extent();
  params_.pixels = frame.pixels().data();
  std::ranges::fill(counters_, LaneCounters{});
}

}  // namespace rt
