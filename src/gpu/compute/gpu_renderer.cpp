#include "gpu/compute/gpu_renderer.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/profiler.h"
#include "gpu/compute/gpu_layout.h"
#include "gpu/compute/raytrace_pipeline.h"
#include "gpu/present/shader_output.h"
#include "gpu/present/swapchain.h"
#include "gpu/vulkan/context.h"
#include "gpu/vulkan/frame_commands.h"
#include "render/accel/bvh.h"
#include "render/accel/sphere_grid.h"
#include "render/accel/wide_bvh.h"
#include "scene/camera.h"

namespace rt::gpu {
namespace {

using PipelineStage = vk::PipelineStageFlagBits;
using Access = vk::AccessFlagBits;

SpecializationConstants specializationFor(const Scene& scene, const RenderOptions& options, const Bvh* bvh,
                                          const WideBvh* wide, const SphereGrid* grid) {
  SpecializationConstants constants{.twoPass = options.algorithm == Algorithm::two_pass ? VK_TRUE : VK_FALSE,
                                    .bounceExit = options.earlyExits.has(EarlyExit::bounce) ? VK_TRUE : VK_FALSE,
                                    .maxDepth = scene.render.maxDepth};
  if (bvh) {
    constants.useBvh = VK_TRUE;
    // The grid's walk stops by the pad of the spheres its cells list
    // (SphereGrid::walkPad), whatever padding the tree's boxes carry.
    const TraversalPadModel pad = grid ? grid->walkPad : bvh->pad;
    constants.bvhPadRadius = pad.radius;
    constants.bvhPadCoordinate = pad.coordinate;
    constants.bvhPadOriginSlope = pad.originSlope;
    constants.bvhStackSize = binaryStackSize(*bvh);
  }
  if (wide) {
    constants.wideBvh = VK_TRUE;
    constants.wideStackSize = wideStackSize(*wide);
  }
  if (grid) {
    constants.grid = VK_TRUE;
    for (int axis = 0; axis < 3; ++axis) {
      constants.gridOrigin[axis] = grid->origin[axis];
      constants.gridCells[axis] = grid->cells[axis];
    }
    constants.gridCellSize = grid->cellSize;
    constants.gridApartCount = static_cast<std::int32_t>(grid->apartCount);
  }
  constants.persistent = options.gpuSchedule == GpuSchedule::persistent ? VK_TRUE : VK_FALSE;
  constants.counters = options.counters ? VK_TRUE : VK_FALSE;
  return constants;
}

std::vector<RaytraceStage> stagesOf(GpuPath path) {
  if (path == GpuPath::wavefront) return {RaytraceStage::wavefrontDepth, RaytraceStage::wavefrontResolve};
  return {RaytraceStage::megakernel};
}

// Rays of a frame as the shader numbers them: whole 8x8 tiles.
std::uint32_t rayCount(Extent extent) {
  return workgroupCount(extent.width, RT_TILE_SIZE) * workgroupCount(extent.height, RT_TILE_SIZE) * RT_TILE_RAYS;
}

// Rows of RT_WAVEFRONT_GROUPS_X workgroups that cover `rays` queued rays.
std::uint32_t wavefrontRows(std::uint32_t rays) {
  constexpr std::uint32_t kRaysPerRow = RT_WAVEFRONT_GROUPS_X * RT_TILE_RAYS;
  return (rays + kRaysPerRow - 1) / kRaysPerRow;
}

// The persistent threads' fetch counters and the wavefront's per-depth
// queue counts and dispatch sizes as every frame starts (gpu_interface.h):
// depth 0 holds every ray, the others none yet.
std::vector<std::uint32_t> initialControl(int maxDepth, Extent extent) {
  std::vector<std::uint32_t> words(static_cast<std::size_t>(maxDepth + 1) * RT_CONTROL_WORDS, 0u);
  for (int depth = 0; depth <= maxDepth; ++depth) {
    std::uint32_t* control = words.data() + static_cast<std::size_t>(depth) * RT_CONTROL_WORDS;
    control[0] = RT_WAVEFRONT_GROUPS_X;
    control[2] = 1;
  }
  words[RT_CONTROL_GROUPS_Y] = wavefrontRows(rayCount(extent));
  words[RT_CONTROL_COUNT] = rayCount(extent);
  return words;
}

// What a buffer of `bytes` the shader binds needs of the device: refused
// with the figure where it passes maxStorageBufferRange.
vk::DeviceSize checkedStorageSize(const Device& device, vk::DeviceSize bytes, const char* what) {
  const vk::DeviceSize limit = device.physical().getProperties().limits.maxStorageBufferRange;
  if (bytes > limit) {
    throw RendererUnavailable("the GPU renderer's " + std::string(what) + " would take " + std::to_string(bytes) +
                              " bytes, more than this device's maxStorageBufferRange (" + std::to_string(limit) +
                              "): choose a smaller image (or a smaller maxDepth)");
  }
  return bytes;
}

// Lavapipe's shader compiler (gallivm) ends an invocation's loops after
// 65535 iterations counted over all of its loops, without an error: past
// that the image is silently cut short (docs/render-model.md section 8,
// measured at 20,000 spheres: maxDepth 3 exact, maxDepth 4 not). Brute
// force loops over every sphere at every bounce, so a frame whose
// invocations would need more is refused there; a BVH walk needs a few
// dozen iterations per ray. An estimate per invocation: the rays it may
// trace (persistent threads take up to twice their fair share), each with
// its bounces over the spheres, and the two-pass backward loop.
constexpr std::uint64_t kLavapipeLoopIterations = 65535;

std::uint64_t bruteForceLoopIterations(std::size_t spheres, int maxDepth, Extent extent, const RenderOptions& options) {
  const std::uint64_t invocations = std::uint64_t{RT_PERSISTENT_WORKGROUPS} * RT_TILE_RAYS;
  const std::uint64_t rays = rayCount(extent);
  const std::uint64_t raysEach =
      options.gpuSchedule == GpuSchedule::persistent ? 2 * ((rays + invocations - 1) / invocations) : 1;
  const auto depth = static_cast<std::uint64_t>(maxDepth);
  const std::uint64_t bounces = options.gpuPath == GpuPath::wavefront ? 1 : depth;
  return raysEach * (bounces * (spheres + 2) + depth);
}

// The f16 SPIR-V declares the Float16 capability, which a device may run
// only with shaderFloat16 enabled at its creation (--precision f16 asks for it).
void requireHalfPrecision(const Device& device, const RenderOptions& options) {
  if (options.precision != Precision::f16 || device.shaderFloat16()) return;
  throw RendererUnavailable(
      "the GPU renderer computes in half precision (--precision f16) only on a device "
      "opened with shaderFloat16 (gpu::ContextOptions::shaderFloat16); this one was not");
}

void refuseLoopsPastLavapipeLimit(const Device& device, const Scene& scene, Extent extent,
                                  const RenderOptions& options) {
  if (options.accel != Accel::none || device.info().driverName != "llvmpipe") return;
  const std::uint64_t needed = bruteForceLoopIterations(scene.spheres.size(), scene.render.maxDepth, extent, options);
  if (needed <= kLavapipeLoopIterations) return;
  throw RendererUnavailable("lavapipe ends a shader invocation's loops after " +
                            std::to_string(kLavapipeLoopIterations) + " iterations, and brute force over " +
                            std::to_string(scene.spheres.size()) + " spheres (maxDepth " +
                            std::to_string(scene.render.maxDepth) + ") would need about " + std::to_string(needed) +
                            ": its image would be cut short; use --accel bvh" +
                            (options.gpuSchedule == GpuSchedule::persistent ? " or --gpu-schedule pixel" : ""));
}

// Subgroup operations the shader's variants use: persistent threads
// (elect, broadcast), the wavefront's queues (ballot) and the counters
// (arithmetic), all in the compute stage.
void requireSubgroupOperations(const Device& device, const RenderOptions& options) {
  if (options.gpuSchedule == GpuSchedule::pixel && options.gpuPath == GpuPath::megakernel && !options.counters) return;
  const auto chain =
      device.physical().getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceSubgroupProperties>();
  const auto& subgroup = chain.get<vk::PhysicalDeviceSubgroupProperties>();
  const vk::SubgroupFeatureFlags needed = vk::SubgroupFeatureFlagBits::eBasic | vk::SubgroupFeatureFlagBits::eBallot |
                                          vk::SubgroupFeatureFlagBits::eArithmetic;
  if (!(subgroup.supportedStages & vk::ShaderStageFlagBits::eCompute) ||
      (subgroup.supportedOperations & needed) != needed) {
    throw RendererUnavailable(
        "this Vulkan device offers no basic, ballot and arithmetic subgroup operations in compute shaders, which "
        "--gpu-schedule persistent, --gpu-path wavefront and --counters need");
  }
}

// A memory barrier between two dispatches of a wavefront frame: the first
// one's queue, state and control writes are seen by the next one's shader
// and by its indirect dispatch size.
void dispatchBarrier(const vk::raii::CommandBuffer& cb) {
  const vk::MemoryBarrier barrier{
      .srcAccessMask = Access::eShaderWrite,
      .dstAccessMask = Access::eShaderRead | Access::eShaderWrite | Access::eIndirectCommandRead};
  cb.pipelineBarrier(PipelineStage::eComputeShader, PipelineStage::eComputeShader | PipelineStage::eDrawIndirect, {},
                     barrier, {}, {});
}

// `data` in a new device-local storage buffer, through a staging buffer:
// the shader reads the scene for every ray, so it must not sit in host
// memory. Waits for the copy; the staging buffer goes on return.
template <typename T>
Buffer uploadStorage(const Device& device, CommandRunner& runner, std::span<const T> data) {
  return uploadToDevice(device, runner, std::as_bytes(data), vk::BufferUsageFlagBits::eStorageBuffer,
                        PipelineStage::eComputeShader, Access::eShaderRead);
}

// The binary walk's tree has one sphere per leaf (kSingleSphereLeaves: with
// the paired stack entries 1.12 to 1.19x faster on the H100 than the CPU
// kernels' leaves from 1,000 spheres up, 2 % slower at 100, slower on
// lavapipe; docs/experiments/gpu-traversal.md); the wide tree is collapsed
// from the CPU kernels' own.
AccelStructure accelFor(const Scene& scene, const RenderOptions& options) {
  AccelStructure accel;
  accel.prepare(scene.spheres, options.accel, options.gpuBvh == GpuBvh::wide ? kBvhLeaves : kSingleSphereLeaves);
  return accel;
}

// The walk's structure on the device (--accel bvh only): the binary tree's
// nodes (its boxes widened by sceneTraversalPad in the tree's pad model) or the grid's
// cells; the scene index of each slot the binary walk or the grid tests
// (the wide walk's are WideBvhBuffers'); and the slots' spheres.
struct BvhBuffers {
  BvhBuffers(const Device& device, CommandRunner& runner, const Bvh& bvh, const Scene& scene, const WideBvh* wide,
             const SphereGrid* grid)
      : nodes(grid ? uploadStorage(device, runner, std::span<const glm::uvec2>(toGpuGridCells(*grid)))
                   : uploadStorage(device, runner,
                                   std::span<const GpuBinaryNode>(toGpuBinaryNodes(
                                       bvh, sceneTraversalPad(bvh, cameraMaxCoordinate(scene.camera)))))),
        order(uploadStorage(device, runner, std::span(grid ? grid->slots : bvh.order))),
        leafSpheres(
            uploadStorage(device, runner,
                          std::span<const glm::vec4>(
                              wide ? gpu::leafSpheres(scene.spheres, std::span(wide->index))
                                   : gpu::leafSpheres(scene.spheres, std::span(grid ? grid->slots : bvh.order))))) {}
  Buffer nodes;  // the grid's cells with the grid
  Buffer order;
  Buffer leafSpheres;
};

// --gpu-bvh wide: the wide tree collapsed from the binary one, on the device.
struct WideBvhBuffers {
  WideBvhBuffers(const Device& device, CommandRunner& runner, const WideBvh& wide)
      : nodes(uploadStorage(device, runner, std::span(wide.nodes))),
        index(uploadStorage(device, runner, std::span(wide.index))) {}
  Buffer nodes;
  Buffer index;
};

std::optional<WideBvh> wideBvhFor(const Scene& scene, const RenderOptions& options, const Bvh* bvh) {
  if (!bvh || options.gpuBvh != GpuBvh::wide) return std::nullopt;
  return buildWideBvh(*bvh, scene.spheres);
}

// What the grid takes on the device: its cells, and each slot's sphere and
// scene index.
std::uint64_t gridDeviceBytes(const SphereGrid& grid) {
  return grid.cellCount() * sizeof(glm::uvec2) + grid.slots.size() * (sizeof(glm::vec4) + sizeof(std::uint32_t));
}

// --gpu-bvh grid: each cell lists the spheres whose surface passes within
// their own traversal pad of it, for every origin the scene's rays can have
// (the tree's bound of every sphere, those kept apart too, and the camera's
// orbit); docs/render-model.md section 3, "The grid".
std::optional<SphereGrid> gridFor(const Scene& scene, const RenderOptions& options, const Bvh* bvh) {
  if (!bvh || options.gpuBvh != GpuBvh::grid) return std::nullopt;
  const float origins = originBound(bvh->maxCoordinate, cameraMaxCoordinate(scene.camera));
  return buildSphereGrid(scene.spheres, sphereGridMargins(scene.spheres, origins));
}

constexpr vk::DeviceSize kCounterBytes =
    vk::DeviceSize{RT_COUNTER_COPIES} * RT_COUNTER_SLOTS * 2 * sizeof(std::uint32_t);

// --counters: the shader's counters on the device, zeroed before each
// frame, and where they are copied for the host after it.
struct CounterBuffers {
  explicit CounterBuffers(const Device& device)
      : counters(device, kCounterBytes,
                 vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst |
                     vk::BufferUsageFlagBits::eTransferSrc,
                 MemoryUse::deviceLocal),
        readback(device, kCounterBytes, vk::BufferUsageFlagBits::eTransferDst, MemoryUse::readback) {}
  Buffer counters;
  Buffer readback;

  // The copies' sums as the LaneCounters fields (gpu_interface.h's slots).
  [[nodiscard]] LaneCounters read() const {
    readback.invalidateForHost();
    std::array<std::uint32_t, kCounterBytes / sizeof(std::uint32_t)> words{};
    std::memcpy(words.data(), readback.mapped().data(), kCounterBytes);
    std::array<std::uint64_t, RT_COUNTER_SLOTS> sums{};
    for (std::size_t copy = 0; copy < RT_COUNTER_COPIES; ++copy) {
      for (std::size_t slot = 0; slot < RT_COUNTER_SLOTS; ++slot) {
        const std::size_t at = (copy * RT_COUNTER_SLOTS + slot) * 2;
        sums[slot] += words[at] | (std::uint64_t{words[at + 1]} << 32);
      }
    }
    LaneCounters counted;
    std::copy_n(sums.begin(), kCountedDepths, counted.raysPerDepth.begin());
    counted.nodeVisits = sums[RT_COUNTER_NODE_VISITS];
    counted.nodeLaneSlots = sums[RT_COUNTER_NODE_LANE_SLOTS];
    counted.nodeLanesActive = counted.nodeVisits;  // an invocation's visit is its own useful work
    counted.sphereTests = sums[RT_COUNTER_SPHERE_TESTS];
    counted.sphereLaneSlots = sums[RT_COUNTER_SPHERE_LANE_SLOTS];
    counted.sphereLanesActive = counted.sphereTests;
    counted.shadeLaneSlots = sums[RT_COUNTER_SHADE_LANE_SLOTS];
    counted.shadeLanesActive = sums[RT_COUNTER_SHADE_LANES_ACTIVE];
    return counted;
  }
};
static_assert(RT_COUNTER_NODE_VISITS == kCountedDepths, "the counter slots after the depths");

Buffer deviceStorage(const Device& device, vk::DeviceSize bytes, const char* what,
                     vk::BufferUsageFlags extraUsage = {}) {
  return Buffer(device, checkedStorageSize(device, bytes, what), vk::BufferUsageFlagBits::eStorageBuffer | extraUsage,
                MemoryUse::deviceLocal);
}

// The fetch counters of persistent threads and, for wavefronts, the ray
// queues, the paths' state and the two-pass segments.
struct ScheduleBuffers {
  ScheduleBuffers(const Device& device, const Scene& scene, Extent extent, const RenderOptions& options)
      : control(deviceStorage(device, initialControl(scene.render.maxDepth, extent).size() * sizeof(std::uint32_t),
                              "control",
                              vk::BufferUsageFlagBits::eIndirectBuffer | vk::BufferUsageFlagBits::eTransferDst)) {
    if (options.gpuPath != GpuPath::wavefront) return;
    constexpr vk::DeviceSize kRayBytes = 32;  // QueuedRay, PathState and StoredSegment alike
    const vk::DeviceSize rays = rayCount(extent);
    queueEven.emplace(deviceStorage(device, rays * kRayBytes, "ray queue"));
    queueOdd.emplace(deviceStorage(device, rays * kRayBytes, "ray queue"));
    pathStates.emplace(deviceStorage(device, rays * kRayBytes, "path states"));
    if (options.algorithm == Algorithm::two_pass) {
      segments.emplace(deviceStorage(device, rays * kRayBytes * static_cast<vk::DeviceSize>(scene.render.maxDepth),
                                     "two-pass segments"));
    }
  }
  Buffer control;
  std::optional<Buffer> queueEven, queueOdd, pathStates, segments;
};

bool usesScheduleBuffers(const RenderOptions& options) {
  return options.gpuSchedule == GpuSchedule::persistent || options.gpuPath == GpuPath::wavefront;
}

}  // namespace

// What prepare() makes for one scene, size and variant. Declared in
// creation order, so the descriptor set goes before the buffer and image
// it names.
struct GPURenderer::SceneObjects {
  SceneObjects(const Device& d, CommandRunner& runner, const Scene& s, Extent e, const RenderOptions& o,
               AccelStructure a, PresentMode mode)
      : scene(s),
        options(o),
        shading(shadingParamsOf(s)),
        extent(e),
        accel(std::move(a)),
        wide(wideBvhFor(s, o, accel.bvh())),
        grid(gridFor(s, o, accel.bvh())),
        pipeline(d, o.precision, specializationFor(s, o, accel.bvh(), wide ? &*wide : nullptr, grid ? &*grid : nullptr),
                 stagesOf(o.gpuPath)),
        spheres(uploadStorage(d, runner, std::span<const GPUSphere>(toGpuSpheres(s.spheres)))),
        bvhBuffers(accel.bvh() ? std::make_optional<BvhBuffers>(d, runner, *accel.bvh(), s, wide ? &*wide : nullptr,
                                                                grid ? &*grid : nullptr)
                               : std::nullopt),
        wideBuffers(wide ? std::make_optional<WideBvhBuffers>(d, runner, *wide) : std::nullopt),
        counterBuffers(o.counters ? std::make_optional<CounterBuffers>(d) : std::nullopt),
        scheduleBuffers(usesScheduleBuffers(o) ? std::make_optional<ScheduleBuffers>(d, s, e, o) : std::nullopt),
        initialControlWords(initialControl(s.render.maxDepth, e)),
        output(d, runner, e, mode, PipelineStage::eComputeShader),
        bindings(d, pipeline, sceneBuffers(), output.image()) {}

  const Scene& scene;
  RenderOptions options;
  ShadingParams shading;  // the push constants' scene part, built once per scene
  Extent extent;
  AccelStructure accel;            // the BVH with --accel bvh; its bounds went into the pipeline
  std::optional<WideBvh> wide;     // --gpu-bvh wide only
  std::optional<SphereGrid> grid;  // --gpu-bvh grid only
  RaytracePipeline pipeline;
  Buffer spheres;
  std::optional<BvhBuffers> bvhBuffers;  // --accel bvh only
  std::optional<WideBvhBuffers> wideBuffers;
  std::optional<CounterBuffers> counterBuffers;    // --counters only
  std::optional<ScheduleBuffers> scheduleBuffers;  // persistent threads or wavefronts only
  std::vector<std::uint32_t> initialControlWords;  // what the control buffer holds as a frame starts
  ShaderOutput output;
  RaytraceBindings bindings;

  // The buffers the shader binds. The spheres stand in for those a variant
  // lacks: a descriptor must name a live buffer, and that pipeline never
  // touches those slots.
  [[nodiscard]] SceneBuffers sceneBuffers() const {
    SceneBuffers buffers = SceneBuffers::allSpheres(spheres.handle());
    if (bvhBuffers) {
      buffers.bvhNodes = bvhBuffers->nodes.handle();
      buffers.bvhOrder = bvhBuffers->order.handle();
      buffers.leafSpheres = bvhBuffers->leafSpheres.handle();
      if (grid) buffers.gridCells = bvhBuffers->nodes.handle();
    }
    if (wideBuffers) {
      buffers.wideNodes = wideBuffers->nodes.handle();
      buffers.wideIndex = wideBuffers->index.handle();
    }
    if (counterBuffers) buffers.counters = counterBuffers->counters.handle();
    if (scheduleBuffers) {
      const ScheduleBuffers& b = *scheduleBuffers;
      buffers.control = b.control.handle();
      const auto handleOr = [&](const std::optional<Buffer>& buffer) {
        return buffer ? buffer->handle() : spheres.handle();
      };
      buffers.queueEven = handleOr(b.queueEven);
      buffers.queueOdd = handleOr(b.queueOdd);
      buffers.pathStates = handleOr(b.pathStates);
      buffers.segments = handleOr(b.segments);
    }
    return buffers;
  }

  // Before the timed dispatches: zero the counters, reset the fetch
  // counters and queue sizes; the dispatches see those writes.
  void recordFrameReset(const vk::raii::CommandBuffer& cb) const {
    if (counterBuffers) {
      cb.fillBuffer(counterBuffers->counters.handle(), 0, VK_WHOLE_SIZE, 0u);
      bufferBarrier(cb, counterBuffers->counters.handle(), PipelineStage::eTransfer, Access::eTransferWrite,
                    PipelineStage::eComputeShader, Access::eShaderRead | Access::eShaderWrite);
    }
    if (scheduleBuffers) {
      cb.updateBuffer<std::uint32_t>(scheduleBuffers->control.handle(), 0, initialControlWords);
      bufferBarrier(cb, scheduleBuffers->control.handle(), PipelineStage::eTransfer, Access::eTransferWrite,
                    PipelineStage::eComputeShader | PipelineStage::eDrawIndirect,
                    Access::eShaderRead | Access::eShaderWrite | Access::eIndirectCommandRead);
    }
  }

  // The frame's dispatches: the megakernel's one, or a wavefront's one per
  // bounce depth and its resolve. Persistent threads launch a fixed grid.
  void recordDispatches(const vk::raii::CommandBuffer& cb, vk::DescriptorSet set,
                        const FrameConstants& constants) const {
    const std::uint32_t tilesAcross = workgroupCount(extent.width, RT_WORKGROUP_SIZE_X);
    const std::uint32_t tilesDown = workgroupCount(extent.height, RT_WORKGROUP_SIZE_Y);
    const bool persistent = options.gpuSchedule == GpuSchedule::persistent;
    if (options.gpuPath == GpuPath::megakernel) {
      pipeline.recordBind(cb, RaytraceStage::megakernel, set, constants);
      if (persistent) {
        cb.dispatch(RT_PERSISTENT_WORKGROUPS, 1, 1);
      } else {
        cb.dispatch(tilesAcross, tilesDown, 1);
      }
      return;
    }
    pipeline.recordBind(cb, RaytraceStage::wavefrontDepth, set, constants);
    for (int depth = 0; depth < scene.render.maxDepth; ++depth) {
      if (depth > 0) dispatchBarrier(cb);
      pipeline.recordWavefrontDepth(cb, depth);
      if (persistent) {
        cb.dispatch(RT_PERSISTENT_WORKGROUPS, 1, 1);
      } else if (depth == 0) {
        cb.dispatch(RT_WAVEFRONT_GROUPS_X, wavefrontRows(rayCount(extent)), 1);
      } else {
        cb.dispatchIndirect(scheduleBuffers->control.handle(),
                            static_cast<vk::DeviceSize>(depth) * RT_CONTROL_WORDS * sizeof(std::uint32_t));
      }
    }
    dispatchBarrier(cb);
    pipeline.recordBind(cb, RaytraceStage::wavefrontResolve, set, constants);
    cb.dispatch(tilesAcross, tilesDown, 1);
  }

  // After the timed dispatches: the counters copied out for the host.
  void recordCounterReadback(const vk::raii::CommandBuffer& cb) const {
    if (!counterBuffers) return;
    bufferBarrier(cb, counterBuffers->counters.handle(), PipelineStage::eComputeShader, Access::eShaderWrite,
                  PipelineStage::eTransfer, Access::eTransferRead);
    cb.copyBuffer(counterBuffers->counters.handle(), counterBuffers->readback.handle(),
                  vk::BufferCopy{.size = kCounterBytes});
  }
};

GPURenderer::GPURenderer(std::shared_ptr<Context> device, PresentMode present, std::shared_ptr<Swapchain> window)
    : context_(std::move(device)), presentMode_(present), window_(std::move(window)) {
  if (!context_) throw std::invalid_argument("the GPU renderer needs a Vulkan device");
  if (presentMode_ == PresentMode::window && !window_)
    throw std::invalid_argument("present mode 'window' needs a swapchain");
  frames_ =
      translateVulkanErrors("GPU renderer set-up", [&] { return std::make_unique<FrameCommands>(context_->device()); });
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
  if (!scene_) return info;
  info.accelStructure = scene_->accel.info();
  if (scene_->grid && info.accelStructure) {
    // The tree only bounded the origins: the grid's cells stand for the nodes, and it has no depth.
    const SphereGrid& grid = *scene_->grid;
    info.accelStructure->buildMs += grid.buildMs;
    info.accelStructure->nodes = grid.cellCount();
    info.accelStructure->depth = std::nullopt;
    info.accelStructure->deviceBytes = gridDeviceBytes(grid);
    info.accelStructure->padding = BoxPadding::local;  // each sphere listed by its own pad (gridFor())
    info.accelStructure->estimatedTestsPerRay = std::nullopt;
    info.accelStructure->spheresKeptApart = grid.apartCount;
  }
  if (scene_->accel.bvh()) info.gpuBvh = scene_->options.gpuBvh;
  info.gpuSchedule = scene_->options.gpuSchedule;
  info.gpuPath = scene_->options.gpuPath;
  info.precision = scene_->options.precision;
  return info;
}

void GPURenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  if (scene.spheres.empty()) throw std::invalid_argument("the GPU renderer needs at least one sphere");
  if (window_) translateVulkanErrors("GPU renderer prepare", [&] { context_->device().logical().waitIdle(); });
  scene_.reset();  // the old objects go before new ones take their memory
  gpuMs_.reset();
  counters_.reset();
  requireSubgroupOperations(context_->device(), options);
  requireHalfPrecision(context_->device(), options);
  // --accel auto is settled here: what follows sees none or bvh.
  AccelStructure accel = accelFor(scene, options);
  RenderOptions resolved = options;
  resolved.accel = accel.bvh() ? Accel::bvh : Accel::none;
  refuseLoopsPastLavapipeLimit(context_->device(), scene, extent, resolved);
  scene_ = translateVulkanErrors("GPU renderer prepare", [&] {
    return std::make_unique<SceneObjects>(context_->device(), frames_->runner(), scene, extent, resolved,
                                          std::move(accel), presentMode_);
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
  using CommandBuffer = vk::raii::CommandBuffer;
  translateVulkanErrors("render", [&] {
    gpuMs_ = frames_->renderFrame(
        "raytrace dispatch",
        [&](const CommandBuffer& cb) {
          s.recordFrameReset(cb);
          s.output.recordBeforeShaderWrites(cb);
        },
        [&](const CommandBuffer& cb) { s.recordDispatches(cb, s.bindings.set(), constants); },
        [&](const CommandBuffer& cb) { s.recordCounterReadback(cb); });
    if (s.counterBuffers) counters_ = s.counterBuffers->read();
  });
}

void GPURenderer::present() { prepared().output.present(frames_->runner(), frames_->profiler(), window_.get()); }

void GPURenderer::readPresented(Image& target) { prepared().output.readPresented(frames_->runner(), target); }

}  // namespace rt::gpu
