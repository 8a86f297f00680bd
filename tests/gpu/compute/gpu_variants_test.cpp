// The GPU renderer's walks (docs/render-model.md section 3, "How the GPU
// renderer walks the BVH"): every BVH and the grid give the bytes of brute
// force, for both algorithms, with and without the bounce exit, on the
// committed scenes (the corpus too) and the scenes built to break a
// traversal; and the shader's counters agree across walks and with what
// the frame must have traced. All under validation.
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
#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
#include "render/scale_scene.h"
#include "scene/camera.h"
#include "test_support.h"

namespace rt::test {
namespace {

constexpr long long kFrame = 25;

// Every walk of the BVH (schema gpu_bvhs) but the reference itself, brute force.
constexpr GpuBvh kAllWalks[] = {GpuBvh::binary, GpuBvh::wide, GpuBvh::grid};

std::string labelOf(GpuBvh walk) { return "bvh/" + std::string(rt::nameOf(walk)); }

RenderOptions withWalk(RenderOptions options, GpuBvh walk) {
  options.accel = Accel::bvh;
  options.gpuBvh = walk;
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
    for (const GpuBvh walk : kAllWalks) {
      const Image image = renderFrame(gpu, scene, extent, withWalk(base, walk), kFrame);
      EXPECT_TRUE(std::ranges::equal(reference.pixels(), image.pixels()))
          << label << " " << extent.width << "x" << extent.height << " " << describeOptions(base) << " "
          << labelOf(walk);
    }
  }
}

class GpuVariants : public ValidatedGpuTest {};

// An odd size leaves partial workgroups, whose invocations past the image do nothing.
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

// Every walk traces the same rays at every depth; brute force tests every
// sphere for each, a walk fewer; the primary rays are one per pixel.
TEST_F(GpuVariants, CountersAgreeAcrossWalks) {
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
    for (const GpuBvh walk : kAllWalks) {
      const LaneCounters counted = countWith(gpu, scene, extent, withWalk(base, walk));
      const std::string label = describeOptions(base) + " " + labelOf(walk);
      EXPECT_EQ(counted.raysPerDepth, reference.raysPerDepth) << label;
      EXPECT_EQ(counted.shadeLanesActive, reference.shadeLanesActive) << label;
      EXPECT_GE(counted.shadeLaneSlots, counted.shadeLanesActive) << label;
      EXPECT_GE(counted.nodeLaneSlots, counted.nodeVisits) << label;
      EXPECT_GE(counted.sphereLaneSlots, counted.sphereTests) << label;
      EXPECT_GT(counted.nodeVisits, 0u) << label;
      EXPECT_LT(counted.sphereTests, reference.sphereTests) << label << ": the BVH tests fewer spheres";
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

// Lavapipe cuts an invocation's loops short after 65535 iterations in all,
// silently; brute force that would need more is refused there, by name,
// and the same frame on the BVH, or with fewer bounces, is not. 20,000
// spheres need about 80,000 iterations at maxDepth 4 and 60,000 at 3 (the
// limit as measured: docs/render-model.md section 8).
TEST_F(GpuVariants, RefusesBruteForcePastLavapipesLoopLimit) {
  if (context()->device().info().driverName != "llvmpipe") GTEST_SKIP() << "lavapipe's limit";
  gpu::GPURenderer gpu(context(), PresentMode::none);
  Scene scene = randomSceneAtScale(20000);
  scene.render.maxDepth = 4;
  RenderOptions options = optionsForStage(Stage::optimized);
  try {
    gpu.prepare(scene, {64, 64}, options);
    FAIL() << "brute force over 20,000 spheres at maxDepth 4 was prepared on lavapipe";
  } catch (const RendererUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("65535"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("use --accel bvh"), std::string::npos) << e.what();
  }
  options.accel = Accel::bvh;
  EXPECT_NO_THROW(gpu.prepare(scene, {64, 64}, options));
  scene.render.maxDepth = 3;
  options.accel = Accel::none;
  EXPECT_NO_THROW(gpu.prepare(scene, {64, 64}, options));
}

// The schedule and the path have one value each since the others were
// retired (schema retired_gpu_variants); the CSV and the metadata still
// record them.
TEST_F(GpuVariants, ReportsItsAxesAfterPrepare) {
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  RenderOptions options = optionsForStage(Stage::optimized);
  renderFrame(gpu, loadNamedScene("default"), {16, 16}, options, kFrame);
  EXPECT_FALSE(gpu.info().gpuBvh.has_value()) << "no BVH with accel none";
  EXPECT_EQ(gpu.info().gpuSchedule, GpuSchedule::pixel);
  EXPECT_EQ(gpu.info().gpuPath, GpuPath::megakernel);
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

// A pile of coincident spheres leaves a walk no box to cull: every ray tests
// all 50,000, which passes lavapipe's limit of 65535 loop iterations where
// its compiler has that limit (Mesa 22.3, Debian 12; Debian 13's Mesa 25.0
// draws the pile right). Either way no frame is silently wrong (render
// model section 8): each tree walk's frame fails, naming the limit, or its
// image is the sequential renderer's. The pile's colours differ, so a walk
// cut short before it reached sphere 0, which wins every tie, would show.
// (The grid would list the pile in thousands of cells, past the storage
// buffers' range.)
TEST_F(GpuVariants, NoWalkDrawsAFrameThatLavapipesLoopLimitCutShort) {
  if (context()->device().info().driverName != "llvmpipe") GTEST_SKIP() << "lavapipe's limit";
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  Scene scene = loadNamedScene("default");
  scene.spheres.clear();
  for (int i = 0; i < 50'000; ++i) {
    const float shade = static_cast<float>(i % 7) / 7.0f;
    scene.spheres.push_back({.position = {0.0f, 0.0f, 0.0f}, .radius = 1.0f, .color = {1.0f - shade, shade, 0.5f}});
  }
  RenderOptions options = optionsForStage(Stage::optimized);
  SequentialRenderer sequential;
  const Image reference = renderFrame(sequential, scene, {8, 8}, options, 0);
  options.accel = Accel::bvh;
  for (const GpuBvh walk : {GpuBvh::binary, GpuBvh::wide}) {
    options.gpuBvh = walk;
    try {
      const Image image = renderFrame(gpu, scene, {8, 8}, options, 0);
      EXPECT_EQ(compareImages(reference, image).fractionWithinTolerance, 1.0) << rt::nameOf(walk);
    } catch (const RendererUnavailable& e) {
      const std::string said = e.what();
      EXPECT_NE(said.find("after 65535 iterations"), std::string::npos) << said;
      EXPECT_NE(said.find("--gpu-bvh " + std::string(rt::nameOf(walk))), std::string::npos) << said;
    }
  }
}

// --gpu-bvh auto =============================================================================

std::vector<std::string> probedCandidates(const RendererInfo& info) {
  std::vector<std::string> names;
  for (const auto& [candidate, ms] : info.gpuWalkProbe->gpuMs) names.push_back(candidate);
  return names;
}

std::string fastestOfProbe(const RendererInfo& info) {
  return std::ranges::min(info.gpuWalkProbe->gpuMs, {}, [](const auto& entry) { return entry.second; }).first;
}

// The probe measures each walk, the fastest runs, and its image is brute
// force's (render model section 3, "Choosing the GPU walk"); with --accel
// bvh brute force is no candidate.
TEST_F(GpuVariants, TheAutoWalkRunsTheFastestOfItsProbeAndDrawsBruteForcesBytes) {
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  for (const char* name : {"ground500", "random1000"}) {
    const Scene scene = loadNamedScene(name);
    const RenderOptions bruteForce = optionsForStage(Stage::optimized);
    RenderOptions options = bruteForce;
    options.accel = Accel::bvh;
    options.gpuBvh = GpuBvh::auto_;
    const Image image = renderFrame(gpu, scene, {24, 16}, options, kFrame);
    const RendererInfo info = gpu.info();
    ASSERT_TRUE(info.gpuWalkProbe.has_value()) << name;
    EXPECT_EQ(probedCandidates(info), (std::vector<std::string>{"binary", "wide", "grid"})) << name;
    EXPECT_EQ(info.gpuWalkProbe->extent.width, 24);
    ASSERT_TRUE(info.gpuBvh.has_value()) << name;
    EXPECT_EQ(std::string(rt::nameOf(*info.gpuBvh)), fastestOfProbe(info)) << name;
    EXPECT_TRUE(std::ranges::equal(renderFrame(gpu, scene, {24, 16}, bruteForce, kFrame).pixels(), image.pixels()))
        << name << " with walk " << rt::nameOf(*info.gpuBvh);
    EXPECT_FALSE(gpu.info().gpuWalkProbe.has_value()) << "a later prepare() without auto probes nothing";
  }
}

// Under --accel auto brute force joins the probe where the tree's price is
// not far under the sphere count (a handful of spheres), not where it is.
TEST_F(GpuVariants, AccelAutoProbesBruteForceOnlyWhereTheTreeMayNotPay) {
  gpu::GPURenderer gpu(context(), PresentMode::upload);
  RenderOptions options = optionsForStage(Stage::optimized);
  options.accel = Accel::auto_;
  options.gpuBvh = GpuBvh::auto_;
  renderFrame(gpu, loadNamedScene("random20"), {24, 16}, options, kFrame);
  ASSERT_TRUE(gpu.info().gpuWalkProbe.has_value());
  EXPECT_EQ(probedCandidates(gpu.info()), (std::vector<std::string>{"binary", "wide", "grid", "none"}));
  const bool bruteForceRuns = fastestOfProbe(gpu.info()) == "none";
  EXPECT_EQ(gpu.info().accelStructure.has_value(), !bruteForceRuns);
  EXPECT_EQ(gpu.info().gpuBvh.has_value(), !bruteForceRuns);
  renderFrame(gpu, loadNamedScene("random1000"), {24, 16}, options, kFrame);
  ASSERT_TRUE(gpu.info().gpuWalkProbe.has_value());
  EXPECT_EQ(probedCandidates(gpu.info()), (std::vector<std::string>{"binary", "wide", "grid"}));
}

}  // namespace
}  // namespace rt::test
