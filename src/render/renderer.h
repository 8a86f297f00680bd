#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"
#include "render/accel/accel_structure_info.h"
#include "render/lane_counters.h"
#include "render/render_options.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt {

// Asked for a renderer this build or this CPU does not have (exit code 2).
class RendererUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// --gpu-bvh auto: the probe prepare() ran to choose the GPU renderer's walk
// (metadata gpu_walk_probe): each candidate's least gpu_ms over its probe
// frames, at the probe's size; "none" stands for brute force.
struct GpuWalkProbe {
  Extent extent;
  std::vector<std::pair<std::string, double>> gpuMs;
};

// How a renderer runs, as recorded in every CSV row and the metadata.
struct RendererInfo {
  RendererKind kind = RendererKind::sequential;
  int threads = 1;
  int lanes = 1;
  std::string simdTarget;  // empty where no SIMD is used
  // How oneTBB splits the frame; empty for renderers that do not use it.
  std::optional<int> grain;
  std::optional<Partition> partition;
  // Known after prepare(); empty with --accel none.
  std::optional<AccelStructureInfo> accelStructure{};
  // Known after prepare(): how the SIMD kernel walks the BVH, and traversal
  // hybrid's threshold as resolved (the default made a number); empty where
  // none applies.
  std::optional<Traversal> traversal{};
  std::optional<int> hybridThreshold{};
  // The GPU renderer's axes as prepare() set them up: the BVH its shader
  // walks (accel bvh only), its schedule and its path (each of one value
  // since the others were retired: schema retired_gpu_variants, recorded
  // in the CSV and the metadata all the same); empty elsewhere.
  std::optional<GpuBvh> gpuBvh{};
  std::optional<GpuSchedule> gpuSchedule{};
  std::optional<GpuPath> gpuPath{};
  std::optional<GpuWalkProbe> gpuWalkProbe{};  // with --gpu-bvh auto only
  // The gpu_rt renderer's hit reorder; empty elsewhere.
  std::optional<GpuRtReorder> gpuRtReorder{};
  // The type of the render model's arithmetic (docs/render-model.md section 10).
  Precision precision = Precision::f32;
};

// One of the thesis' interchangeable renderers. The interface is virtual
// per frame only; the per-ray work behind render() sees flat arrays.
class Renderer {
 public:
  virtual ~Renderer() = default;
  Renderer() = default;
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  [[nodiscard]] virtual RendererInfo info() const = 0;
  // Before the frame loop: takes the scene and sizes every working buffer,
  // so that render() and present() never allocate.
  virtual void prepare(const Scene& scene, Extent extent, const RenderOptions& options) = 0;
  // The Render phase: one frame seen from `camera`.
  virtual void render(const CameraFrame& camera) = 0;
  // The Present phase: hand the frame on to where it is shown (the
  // windowless stand-in for the swapchain image), or leave it where it was
  // rendered. Nothing comes back to the host here.
  virtual void present() = 0;
  // The frame the last present() handed on, copied into `target` (sized
  // like prepare()'s extent). Not part of any timed phase: the frame loop
  // calls it only for frames that are saved, and tests for what they check.
  virtual void readPresented(Image& target) = 0;
  // Device time of the last render() in milliseconds (GPU timestamps);
  // nullopt where the renderer does not measure one.
  [[nodiscard]] virtual std::optional<double> lastGpuMs() const { return std::nullopt; }
  // The last render()'s counters, summed over its threads; nullopt without
  // --counters or where the renderer does not count.
  [[nodiscard]] virtual std::optional<LaneCounters> lastCounters() const { return std::nullopt; }
};

}  // namespace rt
