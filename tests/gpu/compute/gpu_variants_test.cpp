// The GPU renderer's traversal axes (docs/render-model.md section 3, "How
// the GPU renderer walks the BVH"): every BVH, schedule and path gives the
// bytes of the brute-force megakernel, for both algorithms, with and without
// the bounce exit, on the committed scenes (the corpus too) and the scenes
// built to break a traversal; and the shader's counters agree across
// variants and with what the frame must have traced. All under validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "gpu/compute/gpu_renderer.h"
#include "gpu/gpu_test_support.h"
#include "gpu/vulkan/device.h"
#include "render/accel/accel_scenes.h"
#include "render/accel/bvh.h"
#include "render/accel/sphere_grid.h"
#include "render/render_test_support.h"
#include "scene/camera.h"
#include "test_support.h"

namespace rt::test {
namespace {

constexpr long long kFrame = 25;

struct GpuVariant {
  Accel accel;
  GpuBvh bvh;
  GpuSchedule schedule;
  GpuPath path;
};

std::string nameOf(const GpuVariant& v) {
  std::string name(rt::nameOf(v.accel));
  if (v.accel == Accel::bvh) name += "/" + std::string(rt::nameOf(v.bvh));
  return name + "/" + std::string(rt::nameOf(v.schedule)) + "/" + std::string(rt::nameOf(v.path));
}

// Every combination of the axes but the reference itself (brute force, one
// invocation per pixel, megakernel).
std::vector<GpuVariant> allVariants() {
  std::vector<GpuVariant> variants;
  for (const GpuSchedule schedule : {GpuSchedule::pixel, GpuSchedule::persistent}) {
    for (const GpuPath path : {GpuPath::megakernel, GpuPath::wavefront}) {
      if (schedule != GpuSchedule::pixel || path != GpuPath::megakernel)
        variants.push_back({Accel::none, GpuBvh::binary, schedule, path});
      for (const GpuBvh bvh : {GpuBvh::binary, GpuBvh::wide, GpuBvh::grid})
        variants.push_back({Accel::bvh, bvh, schedule, path});
    }
  }
  return variants;
}

RenderOptions withVariant(RenderOptions options, const GpuVariant& v) {
  options.accel = v.accel;
  options.gpuBvh = v.bvh;
  options.gpuSchedule = v.schedule;
  options.gpuPath = v.path;
  return options;
}

// The thesis' stages original (two-pass, no exit) and optimized
// (single-pass, with the exits): both algorithms and both bounce settings.
std::vector<RenderOptions> algorithmsAndExits() {
  return {optionsForStage(Stage::original), optionsForStage(Stage::optimized)};
}

std::string describeOptions(const RenderOptions& o) {
  return std::string(rt::nameOf(o.algorithm)) + " exits " + o.earlyExits.toString();
}

void expectEveryVariantMatchesBruteForce(const Scene& scene, Extent extent, const std::string& label) {
  gpu::GPURenderer gpu(ValidatedGpuEnvironment::context(), PresentMode::upload);
  for (const RenderOptions& base : algorithmsAndExits()) {
    const Image reference = renderFrame(gpu, scene, extent, base, kFrame);
    for (const GpuVariant& variant : allVariants()) {
      const Image image = renderFrame(gpu, scene, extent, withVariant(base, variant), kFrame);
      EXPECT_TRUE(std::ranges::equal(reference.pixels(), image.pixels()))
          << label << " " << extent.width << "x" << extent.height << " " << describeOptions(base) << " "
          << nameOf(variant);
    }
  }
}

class GpuVariants : public ValidatedGpuTest {};

// An odd size leaves partial tiles, which have ray numbers but no pixels.
TEST_F(GpuVariants, CommittedScenesAreByteIdenticalToBruteForce) {
  for (const char* name : kSceneNames) expectEveryVariantMatchesBruteForce(loadNamedScene(name), {45, 29}, name);
}

// The corpus of uneven sizes and density (scripts/rtbench/scenes.py): a
// radius of 1000 beside radii of 0.2, clusters, a crowd on a huge sphere,
// heavy-tailed radii, the camera inside a sky around nests of spheres.
TEST_F(GpuVariants, CorpusScenesAreByteIdenticalToBruteForce) {
  for (const char* name : kCorpusSceneNames) expectEveryVariantMatchesBruteForce(loadNamedScene(name), {24, 16}, name);
}

// Exact ties, nested and touching spheres, a camera inside a huge sphere,
// a thousand spheres for a deep tree (tests/render/accel/accel_scenes.h).
TEST_F(GpuVariants, ScenesBuiltToBreakATraversalAreByteIdenticalToBruteForce) {
  for (const auto& [name, scene] : adversarialScenes()) expectEveryVariantMatchesBruteForce(scene, {37, 21}, name);
}

// Counters ====================================================================================

LaneCounters countWith(gpu::GPURenderer& gpu, const Scene& scene, Extent extent, const RenderOptions& options) {
  RenderOptions counting = options;
  counting.counters = true;
  renderFrame(gpu, scene, extent, counting, kFrame);
  const std::optional<LaneCounters> counters = gpu.lastCounters();
  if (!counters) throw std::logic_error("no counters with --counters");
  return *counters;
}

TEST_F(GpuVariants, CountersAreOffByDefault) {
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  renderFrame(gpu, loadNamedScene("default"), {16, 16}, optionsForStage(Stage::optimized), kFrame);
  EXPECT_FALSE(gpu.lastCounters().has_value());
}

// Every variant traces the same rays at every depth; brute force tests
// every sphere for each; a BVH's walk visits the same nodes whatever the
// schedule and path; the primary rays are one per pixel.
TEST_F(GpuVariants, CountersAgreeAcrossSchedulesAndPaths) {
  const Scene scene = loadNamedScene("random100");
  const Extent extent{45, 29};
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  for (const RenderOptions& base : algorithmsAndExits()) {
    const LaneCounters reference = countWith(gpu, scene, extent, base);
    EXPECT_EQ(reference.raysPerDepth[0], static_cast<std::uint64_t>(extent.width) * extent.height);
    EXPECT_EQ(reference.sphereTests, reference.rays() * scene.spheres.size());
    EXPECT_EQ(reference.nodeVisits, 0u);
    EXPECT_EQ(reference.deepestDepth(), scene.render.maxDepth) << "the scene's rays bounce to the last depth";
    if (!base.earlyExits.has(EarlyExit::bounce)) {
      EXPECT_EQ(reference.rays(), reference.raysPerDepth[0] * static_cast<std::uint64_t>(scene.render.maxDepth))
          << "without the bounce exit every path runs to maxDepth";
    }
    std::vector<std::pair<GpuVariant, LaneCounters>> byBvh;
    for (const GpuVariant& variant : allVariants()) {
      const LaneCounters counted = countWith(gpu, scene, extent, withVariant(base, variant));
      const std::string label = describeOptions(base) + " " + nameOf(variant);
      EXPECT_EQ(counted.raysPerDepth, reference.raysPerDepth) << label;
      EXPECT_EQ(counted.shadeLanesActive, reference.shadeLanesActive) << label;
      EXPECT_GE(counted.shadeLaneSlots, counted.shadeLanesActive) << label;
      EXPECT_GE(counted.nodeLaneSlots, counted.nodeVisits) << label;
      EXPECT_GE(counted.sphereLaneSlots, counted.sphereTests) << label;
      if (variant.accel == Accel::none) {
        EXPECT_EQ(counted.sphereTests, reference.sphereTests) << label;
        continue;
      }
      EXPECT_GT(counted.nodeVisits, 0u) << label;
      EXPECT_LT(counted.sphereTests, reference.sphereTests) << label << ": the BVH tests fewer spheres";
      for (const auto& [other, otherCounts] : byBvh) {
        if (other.bvh != variant.bvh) continue;
        EXPECT_EQ(counted.nodeVisits, otherCounts.nodeVisits) << label << " against " << nameOf(other);
        EXPECT_EQ(counted.sphereTests, otherCounts.sphereTests) << label << " against " << nameOf(other);
      }
      byBvh.emplace_back(variant, counted);
    }
  }
}

// The wide walk visits fewer nodes than the binary one (eight boxes a visit).
TEST_F(GpuVariants, TheWideBvhVisitsFewerNodes) {
  const Scene scene = loadNamedScene("random100");
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  RenderOptions options = optionsForStage(Stage::optimized);
  options.accel = Accel::bvh;
  const LaneCounters binary = countWith(gpu, scene, {45, 29}, options);
  options.gpuBvh = GpuBvh::wide;
  const LaneCounters wide = countWith(gpu, scene, {45, 29}, options);
  EXPECT_LT(wide.nodeVisits, binary.nodeVisits);
}

// Per-bounce wavefronts keep the subgroups full: the shading steps of the
// later bounces waste fewer lanes than the megakernel's, whose dead paths
// idle in their subgroup.
TEST_F(GpuVariants, WavefrontsFillMoreShadingLanesThanTheMegakernel) {
  const Scene scene = loadNamedScene("random100");
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  RenderOptions options = optionsForStage(Stage::optimized);
  const LaneCounters megakernel = countWith(gpu, scene, {64, 64}, options);
  options.gpuPath = GpuPath::wavefront;
  const LaneCounters wavefront = countWith(gpu, scene, {64, 64}, options);
  EXPECT_LT(wavefront.shadeLaneSlots, megakernel.shadeLaneSlots);
  EXPECT_EQ(wavefront.shadeLanesActive, megakernel.shadeLanesActive);
}

// The wavefront's queues hold 32 bytes per pixel: past what the device can
// bind (maxStorageBufferRange, at most 4 GiB) the size is refused, by name.
TEST_F(GpuVariants, RefusesWavefrontBuffersPastTheDeviceLimit) {
  gpu::GPURenderer gpu(context(), PresentMode::none);
  RenderOptions options = optionsForStage(Stage::original);
  options.gpuPath = GpuPath::wavefront;
  try {
    gpu.prepare(loadNamedScene("default"), {16384, 16384}, options);
    FAIL() << "a 16384x16384 wavefront frame was prepared";
  } catch (const RendererUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("maxStorageBufferRange"), std::string::npos) << e.what();
  }
}

// Lavapipe cuts an invocation's loops short after 65535 iterations in all,
// silently; brute force that would need more is refused there, by name,
// and the same frame on the BVH, or one ray per invocation, is not.
TEST_F(GpuVariants, RefusesBruteForcePastLavapipesLoopLimit) {
  if (context()->device().info().driverName != "llvmpipe") GTEST_SKIP() << "lavapipe's limit";
  gpu::GPURenderer gpu(context(), PresentMode::none);
  const Scene scene = loadNamedScene("random1000");
  RenderOptions options = optionsForStage(Stage::optimized);
  options.gpuSchedule = GpuSchedule::persistent;
  try {
    gpu.prepare(scene, {1920, 1080}, options);  // about 32 rays an invocation, 1000 spheres each bounce
    FAIL() << "persistent brute force over 1000 spheres at 1920x1080 was prepared on lavapipe";
  } catch (const RendererUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("65535"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--gpu-schedule pixel"), std::string::npos) << e.what();
  }
  options.gpuSchedule = GpuSchedule::pixel;
  EXPECT_NO_THROW(gpu.prepare(scene, {1920, 1080}, options));
  options.gpuSchedule = GpuSchedule::persistent;
  options.accel = Accel::bvh;
  EXPECT_NO_THROW(gpu.prepare(scene, {1920, 1080}, options));
}

TEST_F(GpuVariants, ReportsItsAxesAfterPrepare) {
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  RenderOptions options = optionsForStage(Stage::optimized);
  options.gpuSchedule = GpuSchedule::persistent;
  options.gpuPath = GpuPath::wavefront;
  renderFrame(gpu, loadNamedScene("default"), {16, 16}, options, kFrame);
  EXPECT_FALSE(gpu.info().gpuBvh.has_value()) << "no BVH with accel none";
  EXPECT_EQ(gpu.info().gpuSchedule, GpuSchedule::persistent);
  EXPECT_EQ(gpu.info().gpuPath, GpuPath::wavefront);
  options.accel = Accel::bvh;
  options.gpuBvh = GpuBvh::wide;
  renderFrame(gpu, loadNamedScene("default"), {16, 16}, options, kFrame);
  EXPECT_EQ(gpu.info().gpuBvh, GpuBvh::wide);
}

// The binary walk builds its tree with one sphere per leaf, a binary tree
// of 2n - 1 nodes over n spheres that never coincide; the wide walk
// collapses the CPU kernels' tree (kBvhLeaves), as the SIMD kernel does.
TEST_F(GpuVariants, TheBinaryWalksTreeHasOneSpherePerLeaf) {
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  const Scene scene = loadNamedScene("random1000");
  RenderOptions options = optionsForStage(Stage::optimized);
  options.accel = Accel::bvh;
  renderFrame(gpu, scene, {16, 16}, options, kFrame);
  ASSERT_TRUE(gpu.info().accelStructure.has_value());
  EXPECT_EQ(gpu.info().accelStructure->nodes, 2 * scene.spheres.size() - 1);
  EXPECT_EQ(gpu.info().accelStructure->nodes, buildBvh(scene.spheres, kSingleSphereLeaves).nodes.size());
  options.gpuBvh = GpuBvh::wide;
  renderFrame(gpu, scene, {16, 16}, options, kFrame);
  ASSERT_TRUE(gpu.info().accelStructure.has_value());
  EXPECT_EQ(gpu.info().accelStructure->nodes, buildBvh(scene.spheres).nodes.size());
}

// The grid is sized and listed as the build alone does it, each sphere by
// its own pad for the scene's origins (so its padding is local); its cells
// stand for the nodes, it has no depth, and the spheres it keeps apart are
// counted (the ground of ground500, none in random1000).
TEST_F(GpuVariants, TheGridReportsItsCellsAsItsNodes) {
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  RenderOptions options = optionsForStage(Stage::optimized);
  options.accel = Accel::bvh;
  options.gpuBvh = GpuBvh::grid;
  for (const auto& [name, apart] : {std::pair{"random1000", 0u}, std::pair{"ground500", 1u}}) {
    const Scene scene = loadNamedScene(name);
    renderFrame(gpu, scene, {16, 16}, options, kFrame);
    const RendererInfo reported = gpu.info();
    EXPECT_EQ(reported.gpuBvh, GpuBvh::grid);
    ASSERT_TRUE(reported.accelStructure.has_value());
    const Bvh bvh = buildBvh(scene.spheres, kSingleSphereLeaves);
    const float origins = originBound(bvh.maxCoordinate, cameraMaxCoordinate(scene.camera));
    const SphereGrid grid = buildSphereGrid(scene.spheres, sphereGridMargins(scene.spheres, origins));
    const AccelStructureInfo& info = *reported.accelStructure;
    EXPECT_EQ(info.nodes, grid.cellCount()) << name;
    EXPECT_FALSE(info.depth.has_value()) << name;
    EXPECT_EQ(info.padding, BoxPadding::local) << name;
    EXPECT_EQ(info.spheresKeptApart, apart) << name;
    EXPECT_EQ(grid.apartCount, apart) << name;
    // Its cells (first slot, count) and each slot's sphere (vec4) and index.
    EXPECT_EQ(info.deviceBytes, grid.cellCount() * 8 + grid.slots.size() * 20) << name;
  }
  options.gpuBvh = GpuBvh::binary;
  renderFrame(gpu, loadNamedScene("ground500"), {16, 16}, options, kFrame);
  EXPECT_FALSE(gpu.info().accelStructure->spheresKeptApart.has_value()) << "a tree keeps none apart";
}

}  // namespace
}  // namespace rt::test
