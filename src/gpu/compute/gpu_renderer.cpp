#include "gpu/compute/gpu_renderer.h"

#include <cstddef>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>

#include "core/profiler.h"
#include "gpu/compute/gpu_layout.h"
#include "gpu/compute/raytrace_pipeline.h"
#include "gpu/present/present_image.h"
#include "gpu/present/swapchain.h"
#include "gpu/vulkan/context.h"
#include "gpu/vulkan/gpu_profiler.h"
#include "gpu/vulkan/timestamps.h"
#include "render/accel/bvh.h"

namespace rt::gpu {
namespace {

using PipelineStage = vk::PipelineStageFlagBits;
using Access = vk::AccessFlagBits;

// The output image's two states: written by the shader in GENERAL, read by
// copies (present, readback) in TRANSFER_SRC_OPTIMAL.
constexpr ImageState kShaderWrite{PipelineStage::eComputeShader, Access::eShaderWrite, vk::ImageLayout::eGeneral};
constexpr ImageState kTransferRead{PipelineStage::eTransfer, Access::eTransferRead,
                                   vk::ImageLayout::eTransferSrcOptimal};

SpecializationConstants specializationFor(const Scene& scene, const RenderOptions& options, const Bvh* bvh) {
  SpecializationConstants constants{.twoPass = options.algorithm == Algorithm::two_pass ? VK_TRUE : VK_FALSE,
                                    .bounceExit = options.earlyExits.has(EarlyExit::bounce) ? VK_TRUE : VK_FALSE,
                                    .maxDepth = scene.render.maxDepth};
  if (bvh) {
    constants.useBvh = VK_TRUE;
    constants.bvhMaxRadius = bvh->maxRadius;
    constants.bvhMaxCoordinate = bvh->maxCoordinate;
  }
  return constants;
}

// `data` in a new device-local storage buffer, through a staging buffer:
// the shader reads the scene for every ray, so it must not sit in host
// memory. Waits for the copy; the staging buffer goes on return.
template <typename T>
Buffer uploadStorage(const Device& device, CommandRunner& runner, std::span<const T> data) {
  const std::span<const std::byte> bytes = std::as_bytes(data);
  Buffer target(device, bytes.size(), vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
                MemoryUse::deviceLocal);
  const Buffer staging(device, bytes.size(), vk::BufferUsageFlagBits::eTransferSrc, MemoryUse::upload);
  std::memcpy(staging.mapped().data(), bytes.data(), bytes.size());
  staging.flushHostWrites();
  runner.run("scene upload", [&](const vk::raii::CommandBuffer& cb) {
    cb.copyBuffer(staging.handle(), target.handle(), vk::BufferCopy{.size = bytes.size()});
    // The data is written before any dispatch reads it.
    bufferBarrier(cb, target.handle(), PipelineStage::eTransfer, Access::eTransferWrite, PipelineStage::eComputeShader,
                  Access::eShaderRead);
  });
  return target;
}

AccelStructure accelFor(const Scene& scene, const RenderOptions& options) {
  AccelStructure accel;
  accel.prepare(scene.spheres, options.accel);
  return accel;
}

// The BVH's nodes and sphere order on the device (--accel bvh only).
struct BvhBuffers {
  BvhBuffers(const Device& device, CommandRunner& runner, const Bvh& bvh)
      : nodes(uploadStorage(device, runner, std::span(bvh.nodes))),
        order(uploadStorage(device, runner, std::span(bvh.order))) {}
  Buffer nodes;
  Buffer order;
};

}  // namespace

// What lives as long as the renderer: one command buffer for every phase and the timestamp queries.
struct GPURenderer::DeviceObjects {
  explicit DeviceObjects(const Device& d) : device(d) {}
  const Device& device;
  CommandRunner runner{device};
  DispatchTimer timer{device};
  GpuProfiler profiler{device, runner};
};

// What prepare() makes for one scene, size and variant. Declared in
// creation order, so the descriptor set goes before the buffer and image
// it names.
struct GPURenderer::SceneObjects {
  SceneObjects(DeviceObjects& d, const Scene& s, Extent e, const RenderOptions& options, PresentMode mode)
      : scene(s),
        shading(shadingParamsOf(s)),
        extent(e),
        accel(accelFor(s, options)),
        pipeline(d.device, specializationFor(s, options, accel.bvh())),
        spheres(uploadStorage(d.device, d.runner, std::span<const GPUSphere>(toGpuSpheres(s.spheres)))),
        bvhBuffers(accel.bvh() ? std::make_optional<BvhBuffers>(d.device, d.runner, *accel.bvh()) : std::nullopt),
        output(d.device, e, vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc),
        bindings(d.device, pipeline, sceneBuffers(), output),
        readback(d.device, frameBytes(e), vk::BufferUsageFlagBits::eTransferDst, MemoryUse::readback) {
    if (mode == PresentMode::upload) presentImage.emplace(d.device, d.runner, e);
  }

  const Scene& scene;
  ShadingParams shading;  // the push constants' scene part, built once per scene
  Extent extent;
  AccelStructure accel;  // the BVH with --accel bvh; its bounds went into the pipeline
  RaytracePipeline pipeline;
  Buffer spheres;
  std::optional<BvhBuffers> bvhBuffers;  // --accel bvh only
  DeviceImage output;
  RaytraceBindings bindings;
  Buffer readback;
  std::optional<PresentImage> presentImage;                    // mode upload only
  vk::ImageLayout outputLayout = vk::ImageLayout::eUndefined;  // as the last submitted commands left it

  // The buffers the shader binds. Without a BVH the spheres stand in for
  // it: a descriptor must name a live buffer, and the brute-force pipeline
  // never reads those slots.
  [[nodiscard]] SceneBuffers sceneBuffers() const {
    if (!bvhBuffers) return {spheres.handle(), spheres.handle(), spheres.handle()};
    return {spheres.handle(), bvhBuffers->nodes.handle(), bvhBuffers->order.handle()};
  }

  // Records the output's move from the shader's writes to copies' reads, once per frame.
  void recordOutputReadable(const vk::raii::CommandBuffer& cb) {
    if (outputLayout == kTransferRead.layout) return;
    if (outputLayout != kShaderWrite.layout) throw std::logic_error("GPU renderer: no frame rendered yet");
    // The shader's writes are complete and visible before a copy reads them.
    imageBarrier(cb, output.handle(), kShaderWrite, kTransferRead);
    outputLayout = kTransferRead.layout;
  }
};

GPURenderer::GPURenderer(std::shared_ptr<Context> device, PresentMode present, std::shared_ptr<Swapchain> window)
    : context_(std::move(device)), presentMode_(present), window_(std::move(window)) {
  if (!context_) throw std::invalid_argument("the GPU renderer needs a Vulkan device");
  if (presentMode_ == PresentMode::window && !window_)
    throw std::invalid_argument("present mode 'window' needs a swapchain");
  device_ =
      translateVulkanErrors("GPU renderer set-up", [&] { return std::make_unique<DeviceObjects>(context_->device()); });
}

GPURenderer::~GPURenderer() {
  if (!window_) return;  // every other phase waited for its own work
  try {
    context_->device().logical().waitIdle();
  } catch (const vk::SystemError&) {
    // A lost device runs nothing that could still read the image.
  }
}

RendererInfo GPURenderer::info() const {
  RendererInfo info;
  info.kind = RendererKind::gpu;
  info.threads = 0;  // the device schedules the work
  info.lanes = 0;
  if (scene_) info.accelStructure = scene_->accel.info();
  return info;
}

void GPURenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  if (scene.spheres.empty()) throw std::invalid_argument("the GPU renderer needs at least one sphere");
  if (window_) translateVulkanErrors("GPU renderer prepare", [&] { context_->device().logical().waitIdle(); });
  scene_.reset();  // the old objects go before new ones take their memory
  gpuMs_.reset();
  scene_ = translateVulkanErrors("GPU renderer prepare", [&] {
    return std::make_unique<SceneObjects>(*device_, scene, extent, options, presentMode_);
  });
}

GPURenderer::SceneObjects& GPURenderer::prepared() {
  if (!scene_) throw std::logic_error("GPU renderer: prepare() was not called");
  return *scene_;
}

void GPURenderer::render(const CameraFrame& camera) {
  SceneObjects& s = prepared();
  const FrameConstants constants =
      makeFrameConstants(s.shading, static_cast<std::uint32_t>(s.scene.spheres.size()), camera, s.extent);
  const DispatchTimer& timer = device_->timer;
  [[maybe_unused]] const GpuProfiler& profiler = device_->profiler;
  translateVulkanErrors("render", [&] {
    device_->runner.run("render", [&](const vk::raii::CommandBuffer& cb) {
      // Last frame's GPU zones have completed (its submit was waited for).
      TracyVkCollect(profiler.context(), *cb);
      timer.recordReset(cb);
      // The last frame's copies out of the image finish before the shader
      // overwrites it; from UNDEFINED, since every pixel is written anew.
      imageBarrier(cb, s.output.handle(), {PipelineStage::eTransfer, {}, vk::ImageLayout::eUndefined}, kShaderWrite);
      s.pipeline.recordBind(cb, s.bindings.set(), constants);
      TracyVkZone(profiler.context(), *cb, "raytrace dispatch");
      timer.recordStart(cb);
      cb.dispatch(workgroupCount(s.extent.width, RT_WORKGROUP_SIZE_X),
                  workgroupCount(s.extent.height, RT_WORKGROUP_SIZE_Y), 1);
      timer.recordEnd(cb);
    });
    s.outputLayout = kShaderWrite.layout;
    gpuMs_ = timer.readMs();
  });
}

void GPURenderer::present() {
  SceneObjects& s = prepared();
  if (window_) {
    translateVulkanErrors("present", [&] {
      // Not waited for: the next frame's dispatch waits for this blit's reads in its barrier.
      window_->present(s.output.handle(), s.extent,
                       [&](const vk::raii::CommandBuffer& cb, std::uint32_t) { s.recordOutputReadable(cb); });
    });
    return;
  }
  if (!s.presentImage) return;  // mode none: the frame stays in the storage image
  translateVulkanErrors("present", [&] {
    device_->runner.run("present", [&](const vk::raii::CommandBuffer& cb) {
      TracyVkZone(device_->profiler.context(), *cb, "present copy");
      s.recordOutputReadable(cb);
      s.presentImage->recordCopyFrom(cb, s.output.handle());
    });
  });
}

void GPURenderer::readPresented(Image& target) {
  SceneObjects& s = prepared();
  if (target.extent() != s.extent) throw std::logic_error("readPresented: target extent differs from the frame's");
  translateVulkanErrors("frame readback", [&] {
    device_->runner.run("frame readback", [&](const vk::raii::CommandBuffer& cb) {
      if (s.presentImage) {
        s.presentImage->recordReadback(cb, s.readback.handle());
      } else {
        s.recordOutputReadable(cb);
        recordImageReadback(cb, s.output.handle(), kTransferRead.layout, s.extent, s.readback.handle());
      }
    });
    copyToImage(s.readback, target);
  });
}

}  // namespace rt::gpu
