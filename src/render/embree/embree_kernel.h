#pragma once
// The Embree reference kernel (renderer `embree`, --embree): Intel Embree
// (4 or 3, through the version layer embree_api.h) answers the spatial
// query, which sphere a ray meets first, for packets of horizontally
// adjacent pixels; shading, the bounce, both algorithms and
// the output are the scalar model's (docs/render-model.md sections 4-7,
// render/scalar/scalar_model.h). It is the renderer a user would otherwise
// pick, kept to compare ours with. Built only with RT_EMBREE
// (RT_HAVE_EMBREE); src/render/embree/README.md lists where Embree's
// sphere test differs from section 3.
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"
#include "render/cpu_contracts.h"
#include "render/embree/embree_api.h"
#include "render/render_options.h"
#include "render/renderer.h"
#include "render/scalar/scalar_model.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt {
namespace embree {

// Each handle owns one reference: the kernel's device lives as long as the
// kernel, its scene until the next prepare().
struct DeviceRelease {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct SceneRelease {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
struct GeometryRelease {
  void operator()(RTCGeometry geometry) const { rtcReleaseGeometry(geometry); }
};
using DeviceHandle = std::unique_ptr<RTCDeviceTy, DeviceRelease>;
using SceneHandle = std::unique_ptr<RTCSceneTy, SceneRelease>;
using GeometryHandle = std::unique_ptr<RTCGeometryTy, GeometryRelease>;

// The widest packet Embree's API has (rtcIntersect16).
inline constexpr int kMaxPacket = 16;

// One pixel of a packet on its way through the bounces.
struct Lane {
  kernel::Ray<float> ray;
  kernel::Vec3<float> color;       // single-pass: accumulated; two-pass: the backward pass's result
  kernel::Vec3<float> throughput;  // single-pass only
  int segments = 0;                // two-pass: segments the forward pass stored
  bool live = false;               // traced at the next depth (false for a span's missing tail pixels)
};

// A worker's working memory, sized in prepare() so a frame never allocates.
// A packet of every width is kept so the type does not depend on the width
// picked at run time; only that one is touched. Over-aligned: whole cache
// lines, so two workers never write to one, and the alignment Embree
// requires of rtcIntersect16's packet and valid mask (64 bytes).
struct alignas(64) Slot {
  RTCRayHit4 packet4;
  RTCRayHit8 packet8;
  RTCRayHit16 packet16;
  alignas(64) std::array<int, kMaxPacket> valid;  // -1: trace the lane, 0: leave it
  std::array<Lane, kMaxPacket> lanes;
};

// What a span reads, never writes: the scene from prepare(), the camera and
// the target image from beginFrame().
struct FrameData {
  RTCScene scene = nullptr;
  kernel::ShadingInputs<float> inputs{};  // inputs.bvh stays null: Embree does the query
  CameraFrame camera{};
  Image* image = nullptr;
};

// Pixels x0..x1-1 of row y, with a worker's slot and two-pass segments
// (maxDepth x packet width, depth-major; empty for single-pass).
using SpanFunction = void (*)(const FrameData& frame, Slot& slot, std::span<kernel::PathSegment<float>> segments, int y,
                              int x0, int x1);

}  // namespace embree

// Same interface as ScalarKernel and SimdKernel (see render/cpu_renderer.h).
class EmbreeKernel {
 public:
  static constexpr Kernel kId = Kernel::embree;

  // Creates the Embree device and picks the packet width: the widest that
  // Embree traces natively on this CPU (16 with AVX-512, 8 with AVX/AVX2,
  // else 4). settings.lanes may force 4, 8 or 16 (tests do; the schema
  // gives this renderer no --lanes): Embree emulates a non-native width.
  // Throws RendererUnavailable when Embree has no device or no packets,
  // std::invalid_argument for another lane count.
  explicit EmbreeKernel(const ParallelSettings& settings = {});

  [[nodiscard]] int lanes() const { return lanes_; }
  // Not a Highway target: Embree picks its own instruction set per CPU and
  // does not report it, so this names the library (non-empty, like every
  // SIMD kernel's; the CSV column says which code ran the packets).
  [[nodiscard]] std::string simdTarget() const { return "embree"; }
  // A span starts at a multiple of the packet width, so --partition tiles
  // never splits a packet.
  [[nodiscard]] int alignment() const { return lanes_; }
  // Embree always traverses its own BVH (the schema's own_accel: the CLI
  // records accel bvh and refuses --accel none); ours is never built for
  // it, so there is none of ours to report.
  [[nodiscard]] std::optional<AccelStructureInfo> accelStructure() const { return std::nullopt; }

  // Builds and commits Embree's scene over the spheres (its BVH build runs
  // here, outside the timed phases), takes the scene's shading inputs,
  // picks the variant the options select and sizes `slots` workers' memory.
  void prepare(const Scene& scene, const RenderOptions& options, int slots);
  void beginFrame(const CameraFrame& camera, Image& frame) {
    frame_.camera = camera;
    frame_.image = &frame;
  }
  // Pixels x0..x1-1 of row y; `slot` (the worker's index) picks its memory.
  void renderSpan(int slot, int y, int x0, int x1) {
    span_(frame_, slots_[static_cast<std::size_t>(slot)], segmentsOf(slot), y, x0, x1);
  }

 private:
  void buildScene(std::span<const Sphere> spheres);
  [[nodiscard]] std::span<kernel::PathSegment<float>> segmentsOf(int slot) {
    return std::span(segments_).subspan(static_cast<std::size_t>(slot) * segmentsPerSlot_, segmentsPerSlot_);
  }

  embree::DeviceHandle device_;
  embree::SceneHandle scene_;
  int lanes_ = 0;
  embree::SpanFunction span_ = nullptr;
  embree::FrameData frame_{};
  std::vector<embree::Slot> slots_;
  std::vector<kernel::PathSegment<float>> segments_;
  std::size_t segmentsPerSlot_ = 0;
};
static_assert(CpuKernel<EmbreeKernel>);

}  // namespace rt
