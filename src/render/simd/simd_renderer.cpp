#include "render/simd/simd_renderer.h"

#include "render/row_bands.h"
#include <algorithm>
#include <stdexcept>
#include <string>

namespace rt {
namespace {

simd::Float3 float3(const glm::vec3& v) { return {v.x, v.y, v.z}; }

// --lanes: 0 (native) or exactly 4, 8 or 16 lanes if the target has them.
simd::LaneKernels selectLanes(const simd::TargetKernels& target, int lanes) {
  if (lanes == ParallelSettings::kNativeLanes) return target.native;
  constexpr int kCapped[] = {4, 8, 16};
  const auto* it = std::ranges::find(kCapped, lanes);
  if (it == std::end(kCapped)) {
    throw std::invalid_argument("lanes must be native, 4, 8 or 16, got " + std::to_string(lanes));
  }
  const simd::LaneKernels& kernels = target.capped[it - std::begin(kCapped)];
  if (kernels.lanes != lanes) {
    throw LanesUnsupported("--lanes " + std::to_string(lanes) + ": the CPU's SIMD target " +
                           simd::targetName(target.target) + " has at most " + std::to_string(target.nativeLanes) +
                           " float lanes");
  }
  return kernels;
}

simd::Variant variantFor(const RenderOptions& options) {
  return {.twoPass = options.algorithm == Algorithm::two_pass,
          .bounceExit = options.earlyExits.has(EarlyExit::bounce),
          .sphereExit = options.earlyExits.has(EarlyExit::sphere),
          .discriminantExit = options.earlyExits.has(EarlyExit::discriminant)};
}

}  // namespace

SIMDRenderer::SIMDRenderer(Threading threading, const ParallelSettings& settings)
    : target_(simd::dispatchedKernels()), kernels_(selectLanes(target_, settings.lanes)) {
  if (threading == Threading::tbb) scheduler_.emplace(settings.threads, settings.grain, settings.partition);
}

RendererInfo SIMDRenderer::info() const {
  if (!scheduler_) return {RendererKind::simd_only, 1, kernels_.lanes, simd::targetName(target_.target), std::nullopt, std::nullopt};
  return {RendererKind::simd_tbb, scheduler_->threads(), kernels_.lanes, simd::targetName(target_.target),
          scheduler_->grain(), scheduler_->partition()};
}

void SIMDRenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  CPURenderer::prepare(scene, extent, options);
  prepareSpheres(scene);
  prepareScratch(scene.render.maxDepth);
  kernel_ = kernels_.variants[variantFor(options).index()];
}

// The spheres as eight contiguous arrays, converted once, not per frame.
void SIMDRenderer::prepareSpheres(const Scene& scene) {
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
  spheres_ = {array(0), array(1), array(2), array(3), array(4), array(5), array(6), array(7), static_cast<int>(n)};
}

void SIMDRenderer::prepareScratch(int maxDepth) {
  constexpr std::size_t kFloatsPerLine = sizeof(CacheLine) / sizeof(float);
  const std::size_t floats = simd::scratchFloats(kernels_.lanes, maxDepth);
  scratchLinesPerSlot_ = (floats + kFloatsPerLine - 1) / kFloatsPerLine;
  const std::size_t slots = scheduler_ ? static_cast<std::size_t>(scheduler_->threads()) : 1;
  scratch_.assign(slots * scratchLinesPerSlot_, CacheLine{});
}

std::span<float> SIMDRenderer::scratchOf(int slot) {
  CacheLine* first = scratch_.data() + static_cast<std::size_t>(slot) * scratchLinesPerSlot_;
  return {first->floats, scratchLinesPerSlot_ * (sizeof(CacheLine) / sizeof(float))};
}

simd::FrameParams SIMDRenderer::frameParams(const CameraFrame& camera) {
  const Scene& s = scene();
  simd::FrameParams f{};
  f.spheres = spheres_;
  f.cameraPosition = float3(camera.position);
  f.forward = float3(camera.forward);
  f.right = float3(camera.right);
  f.up = float3(camera.up);
  f.tanHalfFov = camera.tanHalfFov;
  f.toLight = float3(-s.lightData.directionalLightDirection);
  f.lightColor = float3(s.lightData.directionalLightColor);
  f.ambientColor = float3(s.lightData.ambientLightColor);
  f.background = float3(s.render.background);
  f.reflectivity = s.render.reflectivity;
  f.shininess = s.render.shininess;
  f.specularStrength = s.render.specularStrength;
  f.maxDepth = s.render.maxDepth;
  f.extent = extent();
  f.pixels = workingBuffer().pixels().data();
  return f;
}

void SIMDRenderer::render(const CameraFrame& camera) {
  const simd::FrameParams params = frameParams(camera);
  const Extent e = extent();
  if (!scheduler_) {
    const std::span<float> scratch = scratchOf(0);
    forEachRowBand(e.height, [&](int y) { kernel_(params, y, 0, e.width, scratch); });
    return;
  }
  scheduler_->forEachSpan(e, kernels_.lanes, [&](int slot, int y, int x0, int x1) {
    kernel_(params, y, x0, x1, scratchOf(slot));
  });
}

}  // namespace rt
