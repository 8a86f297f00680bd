#include "gpu/compute/gpu_renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
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

// Lavapipe's loop limit (render model section 8): every frame there finds
// out whether the limit cut a loop short (shaders/loop_guard.glsl); brute
// force is also refused beforehand where it would pass the limit
// (refuseLoopsPastLavapipeLimit below).
bool guardsLoops(const Device& device) { return device.info().driverName == "llvmpipe"; }

SpecializationConstants specializationFor(const Scene& scene, const RenderOptions& options, const Bvh* bvh,
                                          const WideBvh* wide, const SphereGrid* grid, bool loopGuard) {
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
  constants.counters = options.counters ? VK_TRUE : VK_FALSE;
  constants.loopGuard = loopGuard ? VK_TRUE : VK_FALSE;
  return constants;
}

// Lavapipe's shader compiler (gallivm) ends an invocation's loops after
// 65535 iterations counted over all of its loops, without an error: past
// that the image is silently cut short (docs/render-model.md section 8,
// measured at 20,000 spheres: maxDepth 3 exact, maxDepth 4 not). Brute
// force loops over every sphere at every bounce, so a frame whose
// invocations would need more is refused there; a BVH walk needs a few
// dozen iterations per ray. An estimate per invocation, which traces its
// pixel's path: its bounces over the spheres, and the two-pass backward loop.
constexpr std::uint64_t kLavapipeLoopIterations = RT_LAVAPIPE_LOOP_ITERATIONS;

std::uint64_t bruteForceLoopIterations(std::size_t spheres, int maxDepth) {
  const auto depth = static_cast<std::uint64_t>(maxDepth);
  return depth * (spheres + 2) + depth;
}

// The f16 SPIR-V declares the Float16 capability, which a device may run
// only with shaderFloat16 enabled at its creation (--precision f16 asks for it).
void requireHalfPrecision(const Device& device, const RenderOptions& options) {
  if (options.precision != Precision::f16 || device.shaderFloat16()) return;
  throw RendererUnavailable(
      "the GPU renderer computes in half precision (--precision f16) only on a device "
      "opened with shaderFloat16 (gpu::ContextOptions::shaderFloat16); this one was not");
}

void refuseLoopsPastLavapipeLimit(const Device& device, const Scene& scene, const RenderOptions& options) {
  if (options.accel != Accel::none || device.info().driverName != "llvmpipe") return;
  const std::uint64_t needed = bruteForceLoopIterations(scene.spheres.size(), scene.render.maxDepth);
  if (needed <= kLavapipeLoopIterations) return;
  throw RendererUnavailable("lavapipe ends a shader invocation's loops after " +
                            std::to_string(kLavapipeLoopIterations) + " iterations, and brute force over " +
                            std::to_string(scene.spheres.size()) + " spheres (maxDepth " +
                            std::to_string(scene.render.maxDepth) + ") would need about " + std::to_string(needed) +
                            ": its image would be cut short; use --accel bvh");
}

// Subgroup operations the counters use (elect, arithmetic: nearest_hit.glsl's
// reductions), in the compute stage.
void requireSubgroupOperations(const Device& device, const RenderOptions& options) {
  if (!options.counters) return;
  const auto chain =
      device.physical().getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceSubgroupProperties>();
  const auto& subgroup = chain.get<vk::PhysicalDeviceSubgroupProperties>();
  const vk::SubgroupFeatureFlags needed =
      vk::SubgroupFeatureFlagBits::eBasic | vk::SubgroupFeatureFlagBits::eArithmetic;
  if (!(subgroup.supportedStages & vk::ShaderStageFlagBits::eCompute) ||
      (subgroup.supportedOperations & needed) != needed) {
    throw RendererUnavailable(
        "this Vulkan device offers no basic and arithmetic subgroup operations in compute shaders, which "
        "--counters needs");
  }
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

// Lavapipe's guard words (shaders/loop_guard.glsl): host-visible, zeroed
// once; a raised word fails the frame, so it is never reset.
struct LoopGuardBuffer {
  static constexpr std::size_t kWords = 2;  // the raised word, and the guard loop's extra bound (0)

  explicit LoopGuardBuffer(const Device& device)
      : words(device, kWords * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eStorageBuffer, MemoryUse::readback) {
    std::memset(words.mapped().data(), 0, kWords * sizeof(std::uint32_t));
    words.flushHostWrites();
  }
  Buffer words;

  // Throws RendererUnavailable once the shader raised the word.
  void refuseACutShortFrame(const RenderOptions& options) const {
    words.invalidateForHost();
    std::uint32_t raised = 0;
    std::memcpy(&raised, words.mapped().data(), sizeof raised);
    if (raised == 0) return;
    const std::string variant =
        options.accel == Accel::bvh ? "walk (--gpu-bvh " + std::string(nameOf(options.gpuBvh)) + ")" : "brute force";
    throw RendererUnavailable("lavapipe ends a shader invocation's loops after " +
                              std::to_string(RT_LAVAPIPE_LOOP_ITERATIONS) + " iterations, and this frame's " + variant +
                              " reached that limit: its image was cut short; try another --gpu-bvh, a "
                              "CPU renderer, or a GPU device");
  }
};

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

// --gpu-bvh auto (render model section 3, "Choosing the GPU walk"): the
// walks it measures, each a whole variant; brute force joins them under
// --accel auto where the binary tree's estimated tests per ray are not
// under kProbeBruteForceShare of the sphere count (below that, brute force
// was never the faster on any device measured, and on lavapipe its probe
// alone would take seconds).
constexpr std::array kProbedWalks{GpuBvh::binary, GpuBvh::wide, GpuBvh::grid};
constexpr double kProbeBruteForceShare = 0.1;
constexpr int kProbeWarmUpFrames = 1;
constexpr int kProbeMeasuredFrames = 3;
constexpr std::uint64_t kProbeMaxPixels = std::uint64_t{1} << 19;

RenderOptions walkCandidate(const RenderOptions& options, Accel accel, GpuBvh walk) {
  RenderOptions candidate = options;
  candidate.accel = accel;
  candidate.gpuBvh = walk;
  return candidate;
}

bool probesBruteForce(const RenderOptions& options, const Bvh* binaryTree, std::size_t spheres) {
  return options.accel == Accel::auto_ &&
         (!binaryTree || binaryTree->price >= kProbeBruteForceShare * static_cast<double>(spheres));
}

// The probe's frames: the run's size, halved while it has more pixels than
// kProbeMaxPixels (enough rays to fill a large GPU, few enough for lavapipe).
Extent probeExtentFor(Extent extent) {
  const auto pixels = [](Extent e) {
    return static_cast<std::uint64_t>(e.width) * static_cast<std::uint64_t>(e.height);
  };
  while (pixels(extent) > kProbeMaxPixels && extent.width > 1 && extent.height > 1) {
    extent = {.width = extent.width / 2, .height = extent.height / 2};
  }
  return extent;
}

std::string candidateName(const RenderOptions& candidate) {
  return std::string(candidate.accel == Accel::none ? nameOf(Accel::none) : nameOf(candidate.gpuBvh));
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
        pipeline(
            d, o.precision,
            specializationFor(s, o, accel.bvh(), wide ? &*wide : nullptr, grid ? &*grid : nullptr, guardsLoops(d))),
        spheres(uploadStorage(d, runner, std::span<const GPUSphere>(toGpuSpheres(s.spheres)))),
        bvhBuffers(accel.bvh() ? std::make_optional<BvhBuffers>(d, runner, *accel.bvh(), s, wide ? &*wide : nullptr,
                                                                grid ? &*grid : nullptr)
                               : std::nullopt),
        wideBuffers(wide ? std::make_optional<WideBvhBuffers>(d, runner, *wide) : std::nullopt),
        counterBuffers(o.counters ? std::make_optional<CounterBuffers>(d) : std::nullopt),
        loopGuard(guardsLoops(d) ? std::make_optional<LoopGuardBuffer>(d) : std::nullopt),
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
  std::optional<CounterBuffers> counterBuffers;  // --counters only
  std::optional<LoopGuardBuffer> loopGuard;      // lavapipe only
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
    if (loopGuard) buffers.loopGuard = loopGuard->words.handle();
    return buffers;
  }

  // Before the timed dispatch: zero the counters; the dispatch sees that write.
  void recordFrameReset(const vk::raii::CommandBuffer& cb) const {
    if (!counterBuffers) return;
    cb.fillBuffer(counterBuffers->counters.handle(), 0, VK_WHOLE_SIZE, 0u);
    bufferBarrier(cb, counterBuffers->counters.handle(), PipelineStage::eTransfer, Access::eTransferWrite,
                  PipelineStage::eComputeShader, Access::eShaderRead | Access::eShaderWrite);
  }

  // The frame's one dispatch: an invocation per pixel, in whole workgroups.
  void recordDispatch(const vk::raii::CommandBuffer& cb, vk::DescriptorSet set, const FrameConstants& constants) const {
    pipeline.recordBind(cb, set, constants);
    cb.dispatch(workgroupCount(extent.width, RT_WORKGROUP_SIZE_X), workgroupCount(extent.height, RT_WORKGROUP_SIZE_Y),
                1);
  }

  // After the timed dispatch: the counters copied out for the host.
  void recordCounterReadback(const vk::raii::CommandBuffer& cb) const {
    if (!counterBuffers) return;
    bufferBarrier(cb, counterBuffers->counters.handle(), PipelineStage::eComputeShader, Access::eShaderWrite,
                  PipelineStage::eTransfer, Access::eTransferRead);
    cb.copyBuffer(counterBuffers->counters.handle(), counterBuffers->readback.handle(),
                  vk::BufferCopy{.size = kCounterBytes});
  }
};

GPURenderer::GPURenderer(std::shared_ptr<Context> device, PresentMode present, std::shared_ptr<Swapchain> window)
    : DeviceRenderer("GPU renderer", std::move(device), present, std::move(window)) {}

GPURenderer::~GPURenderer() { waitForWindowAtEnd(); }

RendererInfo GPURenderer::info() const {
  RendererInfo info = deviceInfo(RendererKind::gpu);
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
  info.gpuWalkProbe = walkProbe_;
  // The axes' one remaining values (schema retired_gpu_variants), which
  // the CSV and the metadata still record.
  info.gpuSchedule = GpuSchedule::pixel;
  info.gpuPath = GpuPath::megakernel;
  info.precision = scene_->options.precision;
  return info;
}

void GPURenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  beginPrepare(scene);
  scene_.reset();  // the old objects go before new ones take their memory
  counters_.reset();
  walkProbe_.reset();
  requireSubgroupOperations(device(), options);
  requireHalfPrecision(device(), options);
  scene_ = translateVulkanErrors("GPU renderer prepare", [&] {
    return options.gpuBvh == GpuBvh::auto_ ? prepareFastestWalk(scene, extent, options)
                                           : prepareVariant(scene, extent, options, accelFor(scene, options));
  });
}

// One variant's objects; --accel auto is settled here (by the tree's
// price), so what follows sees none or bvh.
std::unique_ptr<GPURenderer::SceneObjects> GPURenderer::prepareVariant(const Scene& scene, Extent extent,
                                                                       const RenderOptions& options,
                                                                       AccelStructure accel) {
  RenderOptions resolved = options;
  resolved.accel = accel.bvh() ? Accel::bvh : Accel::none;
  refuseLoopsPastLavapipeLimit(device(), scene, resolved);
  return std::make_unique<SceneObjects>(device(), frames().runner(), scene, extent, resolved, std::move(accel),
                                        presentMode());
}

// --gpu-bvh auto: renders frame 0 with each candidate at the probe's size
// and keeps the one with the least gpu_ms (walkProbe_ records them all).
// A candidate this device refuses (brute force past lavapipe's loop limit)
// or whose probe frame passes lavapipe's loop limit is left out.
std::unique_ptr<GPURenderer::SceneObjects> GPURenderer::prepareFastestWalk(const Scene& scene, Extent extent,
                                                                           const RenderOptions& options) {
  const Extent probeExtent = probeExtentFor(extent);
  const CameraFrame camera = cameraAtFrame(scene.camera, 0);
  std::vector<RenderOptions> candidates;
  for (GpuBvh walk : kProbedWalks) candidates.push_back(walkCandidate(options, Accel::bvh, walk));
  GpuWalkProbe probe{.extent = probeExtent, .gpuMs = {}};
  std::unique_ptr<SceneObjects> best;
  double bestMs = 0.0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    std::unique_ptr<SceneObjects> objects;
    try {
      refuseLoopsPastLavapipeLimit(device(), scene, candidates[i]);
      objects = prepareVariant(scene, probeExtent, candidates[i], accelFor(scene, candidates[i]));
    } catch (const RendererUnavailable&) {
      continue;
    }
    if (i == 0 && probesBruteForce(options, objects->accel.bvh(), scene.spheres.size())) {
      candidates.push_back(walkCandidate(options, Accel::none, GpuBvh::binary));
    }
    double ms = 0.0;
    try {
      ms = probeGpuMs(*objects, camera);
    } catch (const RendererUnavailable&) {
      continue;  // its walk passes lavapipe's loop limit
    }
    probe.gpuMs.emplace_back(candidateName(candidates[i]), ms);
    if (!best || ms < bestMs) std::tie(best, bestMs) = std::pair(std::move(objects), ms);
  }
  if (!best) throw RendererUnavailable("--gpu-bvh auto: this device refused every walk it could choose");
  walkProbe_ = std::move(probe);
  if (probeExtent.width == extent.width && probeExtent.height == extent.height) return best;
  const RenderOptions chosen = best->options;
  AccelStructure accel = std::move(best->accel);
  best.reset();
  return prepareVariant(scene, extent, chosen, std::move(accel));
}

// The least gpu_ms of the probe's measured frames, after its warm-up (the
// host's wall time of the frame on a queue without timestamps).
double GPURenderer::probeGpuMs(SceneObjects& objects, const CameraFrame& camera) {
  for (int frame = 0; frame < kProbeWarmUpFrames; ++frame) renderWith(objects, camera);
  double least = std::numeric_limits<double>::infinity();
  for (int frame = 0; frame < kProbeMeasuredFrames; ++frame) {
    const auto start = std::chrono::steady_clock::now();
    const std::optional<double> gpuMs = renderWith(objects, camera);
    const std::chrono::duration<double, std::milli> wall = std::chrono::steady_clock::now() - start;
    least = std::min(least, gpuMs.value_or(wall.count()));
  }
  return least;
}

GPURenderer::SceneObjects& GPURenderer::prepared() {
  if (!scene_) throw std::logic_error("GPU renderer: prepare() was not called");
  return *scene_;
}

// One frame of `s`'s variant: its dispatches between GPU timestamps. On
// lavapipe a frame that its loop limit cut short throws.
std::optional<double> GPURenderer::renderWith(SceneObjects& s, const CameraFrame& camera) {
  const FrameConstants constants =
      makeFrameConstants(s.shading, static_cast<std::uint32_t>(s.scene.spheres.size()), camera, s.extent);
  using CommandBuffer = vk::raii::CommandBuffer;
  const std::optional<double> gpuMs = frames().renderFrame(
      "raytrace dispatch",
      [&](const CommandBuffer& cb) {
        s.recordFrameReset(cb);
        s.output.recordBeforeShaderWrites(cb);
      },
      [&](const CommandBuffer& cb) { s.recordDispatch(cb, s.bindings.set(), constants); },
      [&](const CommandBuffer& cb) { s.recordCounterReadback(cb); });
  if (s.loopGuard) s.loopGuard->refuseACutShortFrame(s.options);
  return gpuMs;
}

void GPURenderer::render(const CameraFrame& camera) {
  SceneObjects& s = prepared();
  translateVulkanErrors("render", [&] {
    gpuMs_ = renderWith(s, camera);
    if (s.counterBuffers) counters_ = s.counterBuffers->read();
  });
}

ShaderOutput& GPURenderer::output() { return prepared().output; }

}  // namespace rt::gpu
