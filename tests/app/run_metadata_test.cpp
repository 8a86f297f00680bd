#include "app/run_metadata.h"

#include <gtest/gtest.h>

#include "core/sha256.h"
#include "render/cpu_renderers.h"
#include "rt_schema_metadata.h"
#include "test_support.h"

namespace rt {
namespace {

// The default scene's run with the sequential renderer and default options,
// as most tests here start.
struct SequentialRun {
  RunConfig config;
  Scene scene;
  std::chrono::system_clock::time_point now = std::chrono::system_clock::now();
  RunIdentity id;

  SequentialRun()
      : config(configOf("default")),
        scene(loadScene(config.scenePath)),
        id{makeRunId(now), scene.name, SequentialRenderer().info(), config.options, config.extent} {}

  static RunConfig configOf(const char* sceneName) {
    RunConfig c;
    c.scenePath = test::scenePath(sceneName);
    return c;
  }
};

TEST(RunMetadata, HasEverySchemaKeyAndTheSceneHash) {
  RunConfig config;
  config.scenePath = test::scenePath("default");
  config.commandLine = {"raytracer", "--sequential"};
  const Scene scene = loadScene(config.scenePath);
  const auto now = std::chrono::system_clock::now();
  const RunIdentity id{makeRunId(now), scene.name, SequentialRenderer().info(), config.options, config.extent};
  const nlohmann::json meta = makeRunMetadata(config, id, scene, {now, now});
  for (auto key : schema::kRunMetadataKeyNames) EXPECT_TRUE(meta.contains(std::string(key))) << key;
  EXPECT_EQ(meta.size(), schema::kRunMetadataKeyNames.size());
  EXPECT_EQ(meta["scene"]["sha256"], sha256HexOfFile(config.scenePath));
  EXPECT_EQ(meta["run_id"], id.runId);
  EXPECT_EQ(meta["config"]["renderer"], "sequential");
  EXPECT_GE(meta["host"]["logical_cores"].get<int>(), 1);
  const auto commit = meta["build"]["git_commit"].get<std::string>();
  EXPECT_TRUE(commit.size() == 40 || commit == "unknown") << commit;
}

// /proc/cpuinfo as x86-64 and aarch64 Linux begin it; the binary's own
// architecture is the native one, the other the foreign one.
constexpr std::string_view kX86Cpuinfo = "processor\t: 0\nvendor_id\t: AuthenticAMD\nmodel name\t: AMD EPYC\n";
constexpr std::string_view kArmCpuinfo = "processor\t: 0\nBogoMIPS\t: 48.00\nCPU implementer\t: 0x41\n";
#if defined(__aarch64__)
constexpr std::string_view kNativeCpuinfo = kArmCpuinfo, kForeignCpuinfo = kX86Cpuinfo;
constexpr std::string_view kForeignArchitecture = "x86_64";
#else
constexpr std::string_view kNativeCpuinfo = kX86Cpuinfo, kForeignCpuinfo = kArmCpuinfo;
constexpr std::string_view kForeignArchitecture = "aarch64";
#endif

TEST(RunEmulation, ANativeProcessOnItsOwnArchitectureIsNotEmulated) {
  EXPECT_EQ(emulationOf("raytracer", kNativeCpuinfo, ""), std::nullopt);
  // A QEMU_CPU left in the environment does not make a native run emulated.
  EXPECT_EQ(emulationOf("raytracer", kNativeCpuinfo, "max"), std::nullopt);
  // Nor does a /proc/cpuinfo that names no architecture we know.
  EXPECT_EQ(emulationOf("raytracer", "processor\t: 0\n", ""), std::nullopt);
}

TEST(RunEmulation, QemuUserIsKnownByItsProcessNameAndNamesTheEmulatedCpu) {
  const auto e = emulationOf("qemu-aarch64", kNativeCpuinfo, "cortex-a72");
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->emulator, "qemu-aarch64");
  EXPECT_EQ(e->cpu, "cortex-a72");
  const auto unnamed = emulationOf("qemu-aarch64", kForeignCpuinfo, "");
  ASSERT_TRUE(unnamed.has_value());
  EXPECT_EQ(unnamed->cpu, std::nullopt);
  EXPECT_EQ(unnamed->hostArchitecture, kForeignArchitecture);
}

TEST(RunEmulation, AForeignCpuinfoGivesAnUnnamedEmulatorAway) {
  const auto e = emulationOf("raytracer", kForeignCpuinfo, "");
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->emulator, "unknown");
  EXPECT_EQ(e->hostArchitecture, kForeignArchitecture);
}

TEST(RunMetadata, RecordsTheLoadAndPrepareTimes) {
  const SequentialRun run;
  const auto& [config, scene, now, id] = run;
  const nlohmann::json meta = makeRunMetadata(config, id, scene, {now, now, 12.5, 34.25});
  EXPECT_EQ(meta["scene"]["load_ms"], 12.5);
  EXPECT_EQ(meta["prepare_ms"], 34.25);
}

TEST(RunMetadata, WindowObjectIsTheRunsWindowOutcome) {
  const SequentialRun run;
  const auto& [config, scene, now, id] = run;
  EXPECT_TRUE(makeRunMetadata(config, id, scene, {now, now})["window"].is_null());
  const WindowOutcome window{.swapchain = {.surfaceFormat = "B8G8R8A8_SRGB", .imageCount = 3, .framesPresented = 7},
                             .closed = true};
  const nlohmann::json written = makeRunMetadata(config, id, scene, {now, now}, window)["window"];
  EXPECT_EQ(written["surface_format"], "B8G8R8A8_SRGB");
  EXPECT_EQ(written["swapchain_images"], 3);
  EXPECT_EQ(written["frames_presented"], 7);
  EXPECT_EQ(written["closed"], true);
}

// Where no traversal applies the config says so as the CSV does (""), and
// without --counters there are no totals.
TEST(RunMetadata, TraversalAndCountersOfARendererWithout) {
  const SequentialRun run;
  const auto& [config, scene, now, id] = run;
  const nlohmann::json meta = makeRunMetadata(config, id, scene, {now, now});
  EXPECT_EQ(meta["config"]["traversal"], "");
  EXPECT_TRUE(meta["config"]["hybrid_threshold"].is_null());
  EXPECT_EQ(meta["config"]["counters"], false);
  EXPECT_TRUE(meta["lane_counters"].is_null());
}

// The GPU renderer's axes in the config, as in the CSV: "" where none
// applies (a CPU renderer; gpu_bvh also with accel none).
TEST(RunMetadata, GpuAxesAreTheRenderersOrEmpty) {
  RunConfig config;
  config.scenePath = test::scenePath("default");
  const Scene scene = loadScene(config.scenePath);
  const auto now = std::chrono::system_clock::now();
  RunIdentity id{makeRunId(now), scene.name, SequentialRenderer().info(), config.options, config.extent};
  nlohmann::json meta = makeRunMetadata(config, id, scene, {now, now});
  for (const char* key : {"gpu_bvh", "gpu_schedule", "gpu_path"}) EXPECT_EQ(meta["config"][key], "") << key;
  id.renderer = RendererInfo{};
  id.renderer.kind = RendererKind::gpu;
  id.renderer.gpuSchedule = GpuSchedule::pixel;
  id.renderer.gpuPath = GpuPath::megakernel;
  meta = makeRunMetadata(config, id, scene, {now, now});
  EXPECT_EQ(meta["config"]["renderer"], "gpu");
  EXPECT_EQ(meta["config"]["gpu_bvh"], "") << "accel none: no BVH";
  EXPECT_EQ(meta["config"]["gpu_schedule"], "pixel");
  EXPECT_EQ(meta["config"]["gpu_path"], "megakernel");
  id.renderer.gpuBvh = GpuBvh::wide;
  meta = makeRunMetadata(config, id, scene, {now, now});
  EXPECT_EQ(meta["config"]["gpu_bvh"], "wide");
  EXPECT_EQ(meta["config"]["traversal"], "") << "the SIMD kernel's key stays empty";
}

TEST(RunMetadata, LaneCountersHoldEverySchemaKeyOfTheTotals) {
  RunConfig config;
  config.scenePath = test::scenePath("default");
  config.options.counters = true;
  const Scene scene = loadScene(config.scenePath);
  const auto now = std::chrono::system_clock::now();
  RendererInfo renderer;
  renderer.kind = RendererKind::simd_tbb;
  renderer.traversal = Traversal::single;
  const RunIdentity id{makeRunId(now), scene.name, renderer, config.options, config.extent};
  LaneCounters totals;
  totals.raysPerDepth[0] = 9000;
  totals.raysPerDepth[1] = 4000;
  totals.nodeVisits = 21;
  totals.nodeLaneSlots = 22;
  totals.nodeLanesActive = 23;
  totals.sphereTests = 24;
  totals.sphereLaneSlots = 25;
  totals.sphereLanesActive = 26;
  totals.shadeLaneSlots = 27;
  totals.shadeLanesActive = 28;
  const nlohmann::json meta = makeRunMetadata(config, id, scene, {now, now}, std::nullopt, totals);
  const nlohmann::json& written = meta["lane_counters"];
  ASSERT_TRUE(written.is_object());
  EXPECT_EQ(written.size(), schema::kMetadataLaneCountersKeyNames.size());
  EXPECT_EQ(written["rays"], 13000);
  EXPECT_EQ(written["rays_per_depth"], nlohmann::json::array({9000, 4000}));
  EXPECT_EQ(written["node_visits"], 21);
  EXPECT_EQ(written["node_lane_slots"], 22);
  EXPECT_EQ(written["node_lanes_active"], 23);
  EXPECT_EQ(written["sphere_tests"], 24);
  EXPECT_EQ(written["sphere_lane_slots"], 25);
  EXPECT_EQ(written["sphere_lanes_active"], 26);
  EXPECT_EQ(written["shade_lane_slots"], 27);
  EXPECT_EQ(written["shade_lanes_active"], 28);
  EXPECT_EQ(meta["config"]["traversal"], "single");
  EXPECT_TRUE(meta["config"]["hybrid_threshold"].is_null()) << "null unless hybrid";
  EXPECT_EQ(meta["config"]["counters"], true);
}

TEST(RunMetadata, TimesAreRfc3339Utc) {
  const auto t = std::chrono::system_clock::time_point(std::chrono::milliseconds(1'700'000'000'123));
  EXPECT_EQ(formatRfc3339(t), "2023-11-14T22:13:20.123Z");
  EXPECT_EQ(makeRunId(t).rfind("20231114T221320Z-", 0), 0u);
}

}  // namespace
}  // namespace rt
