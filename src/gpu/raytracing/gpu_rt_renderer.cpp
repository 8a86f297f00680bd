#include "gpu/raytracing/gpu_rt_renderer.h"

#include <span>
#include <stdexcept>

#include "core/profiler.h"
#include "gpu/compute/gpu_layout.h"
#include "gpu/present/shader_output.h"
#include "gpu/raytracing/ray_tracing_pipeline.h"
#include "gpu/raytracing/sphere_acceleration.h"
#include "gpu/vulkan/frame_commands.h"

namespace rt::gpu {
namespace {

RayTracingVariant variantFor(const Scene& scene, const RenderOptions& options) {
  return {.twoPass = options.algorithm == Algorithm::two_pass ? VK_TRUE : VK_FALSE,
          .bounceExit = options.earlyExits.has(EarlyExit::bounce) ? VK_TRUE : VK_FALSE,
          .maxDepth = scene.render.maxDepth,
          .reorder = options.gpuRtReorder == GpuRtReorder::hit};
}

Buffer uploadSpheres(const Device& device, CommandRunner& runner, std::span<const Sphere> spheres) {
  const std::vector<GPUSphere> data = toGpuSpheres(spheres);
  return uploadToDevice(device, runner, std::as_bytes(std::span(data)), vk::BufferUsageFlagBits::eStorageBuffer,
                        vk::PipelineStageFlagBits::eRayTracingShaderKHR, vk::AccessFlagBits::eShaderRead);
}

}  // namespace

// What prepare() makes for one scene, size and variant, in creation order.
struct GpuRtRenderer::SceneObjects {
  SceneObjects(const Device& d, CommandRunner& runner, const Scene& s, Extent e, const RenderOptions& o,
               PresentMode mode)
      : scene(s),
        options(o),
        shading(shadingParamsOf(s)),
        extent(e),
        structure(d, runner, s),
        pipeline(d, runner, variantFor(s, o)),
        spheres(uploadSpheres(d, runner, s.spheres)),
        output(d, runner, e, mode, vk::PipelineStageFlagBits::eRayTracingShaderKHR),
        bindings(d, pipeline, structure.topLevel(), spheres.handle(), output.image()) {}

  const Scene& scene;
  RenderOptions options;
  ShadingParams shading;
  Extent extent;
  SphereAccelerationStructure structure;
  RayTracingPipeline pipeline;
  Buffer spheres;
  ShaderOutput output;
  RayTracingBindings bindings;
};

GpuRtRenderer::GpuRtRenderer(std::shared_ptr<Context> device, PresentMode present, std::shared_ptr<Swapchain> window)
    : DeviceRenderer("ray-tracing pipeline renderer", std::move(device), present, std::move(window)) {}

GpuRtRenderer::~GpuRtRenderer() { waitForWindowAtEnd(); }

RendererInfo GpuRtRenderer::info() const {
  RendererInfo info = deviceInfo(RendererKind::gpu_rt);
  if (!scene_) return info;
  info.accelStructure = AccelStructureInfo{.kind = Accel::bvh,
                                           .buildMs = scene_->structure.buildMs(),
                                           .nodes = std::nullopt,
                                           .depth = std::nullopt,
                                           .deviceBytes = scene_->structure.deviceBytes(),
                                           .padding = std::nullopt,  // the driver's boxes, each padded by its sphere
                                           .estimatedTestsPerRay = std::nullopt,
                                           .spheresKeptApart = std::nullopt};
  info.gpuRtReorder = scene_->options.gpuRtReorder;
  return info;
}

void GpuRtRenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  beginPrepare(scene);
  scene_.reset();  // the old objects go before new ones take their memory
  scene_ = translateVulkanErrors("ray-tracing pipeline renderer prepare", [&] {
    return std::make_unique<SceneObjects>(device(), frames().runner(), scene, extent, options, presentMode());
  });
}

GpuRtRenderer::SceneObjects& GpuRtRenderer::prepared() {
  if (!scene_) throw std::logic_error("ray-tracing pipeline renderer: prepare() was not called");
  return *scene_;
}

void GpuRtRenderer::render(const CameraFrame& camera) {
  SceneObjects& s = prepared();
  const FrameConstants constants =
      makeFrameConstants(s.shading, static_cast<std::uint32_t>(s.scene.spheres.size()), camera, s.extent);
  using CommandBuffer = vk::raii::CommandBuffer;
  translateVulkanErrors("render", [&] {
    gpuMs_ = frames().renderFrame(
        "trace rays", [&](const CommandBuffer& cb) { s.output.recordBeforeShaderWrites(cb); },
        [&](const CommandBuffer& cb) { s.pipeline.recordTrace(cb, s.bindings.set(), constants, s.extent); },
        [](const CommandBuffer&) {});
  });
}

ShaderOutput& GpuRtRenderer::output() { return prepared().output; }

}  // namespace rt::gpu
