#include "render/simd/simd_kernel.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "render/kernel_variant.h"

namespace rt {
namespace {

// --lanes: native, or exactly one of the schema's lane widths if the target has it.
simd::LaneKernels selectLanes(const simd::TargetKernels& target, int lanes) {
  if (lanes == ParallelSettings::kNativeLanes) return target.native;
  const auto* it = std::ranges::find(schema::kLaneWidths, lanes);
  if (it == schema::kLaneWidths.end()) {
    throw std::invalid_argument("lanes " + std::to_string(lanes) + " is not one of the schema's lane widths");
  }
  const simd::LaneKernels& kernels = target.capped[static_cast<std::size_t>(it - schema::kLaneWidths.begin())];
  if (kernels.lanes != lanes) {
    throw LanesUnsupported("--lanes " + std::to_string(lanes) + ": the CPU's SIMD target " +
                           simd::targetName(target.target) + " has at most " + std::to_string(target.nativeLanes) +
                           " float lanes");
  }
  return kernels;
}

}  // namespace

SimdKernel::SimdKernel(const ParallelSettings& settings)
    : target_(simd::dispatchedKernels()), kernels_(selectLanes(target_, settings.lanes)) {}

void SimdKernel::prepare(const Scene& scene, const RenderOptions& options, int slots) {
  prepareSpheres(scene);
  accel_.prepare(scene.spheres, options.accel);
  params_.spheres.bvh = accel_.bvh();
  prepareScratch(scene.render.maxDepth, slots);
  params_.shading = shadingParamsOf(scene);
  kernel_ = kernels_.variants[KernelVariant::of(options).index()];
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
  params_.spheres = {array(0), array(1), array(2), array(3),           array(4),
                     array(5), array(6), array(7), static_cast<int>(n)};
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
  params_.cameraPosition = camera.position;
  params_.forward = camera.forward;
  params_.right = camera.right;
  params_.up = camera.up;
  params_.tanHalfFov = camera.tanHalfFov;
  params_.extent = frame.extent();
  params_.pixels = frame.pixels().data();
}

}  // namespace rt
