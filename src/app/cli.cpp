#include "app/cli.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <charconv>
#include <concepts>
#include <sstream>
#include <utility>

#include "app/build_info.h"

namespace rt {
namespace {

template <typename Enum, std::size_t N>
std::optional<Enum> enumByName(const std::array<std::string_view, N>& names, std::string_view name) {
  const auto it = std::ranges::find(names, name);
  if (it == names.end()) return std::nullopt;
  return static_cast<Enum>(it - names.begin());
}

template <std::size_t N>
std::string joinNames(const std::array<std::string_view, N>& names, std::string_view separator) {
  std::string joined;
  for (auto n : names) joined += (joined.empty() ? "" : std::string(separator)) + std::string(n);
  return joined;
}

EarlyExitSet parseEarlyExits(const std::string& text) {
  if (text == "none") return EarlyExitSet();
  if (text == "all") return EarlyExitSet::all();
  EarlyExitSet set;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    const auto exit = enumByName<EarlyExit>(schema::kEarlyExitNames, item);
    if (!exit) {
      throw CLI::ValidationError("--early-exit", "unknown early exit '" + item + "' (none, all, or a list of " +
                                                     joinNames(schema::kEarlyExitNames, ",") + ")");
    }
    set.add(*exit);
  }
  return set;
}

SaveFrameRequest parseSaveFrame(const std::string& text) {
  const auto colon = text.find(':');
  SaveFrameRequest request;
  const char* end = text.data() + (colon == std::string::npos ? 0 : colon);
  const auto [ptr, ec] = std::from_chars(text.data(), end, request.frame);
  if (colon == std::string::npos || colon == 0 || ec != std::errc() || ptr != end || request.frame < 0 ||
      colon + 1 == text.size()) {
    throw CLI::ValidationError("--save-frame", "expected K:FILE.png with K >= 0, got '" + text + "'");
  }
  request.file = text.substr(colon + 1);
  return request;
}

// The CLI options of the renderer options, in schema order; null until added.
using RendererOptionSlots = std::array<CLI::Option*, schema::kRendererOptionNames.size()>;

// What CLI11 parses into text first; converted and checked after parsing.
struct RawOptions {
  std::array<bool, schema::kRendererKindNames.size()> rendererFlags{};
  std::string scene;
  std::string algorithm, earlyExit, stage, accel;
  std::string traversal;
  int hybridThreshold = RenderOptions::kDefaultHybridThreshold;
  CLI::Option* hybridThresholdOption = nullptr;
  bool counters = false;
  std::string gpuBvh, gpuRtReorder;
  std::string precision;
  std::string lanes = "native";
  std::string partition;
  std::string csv, meta, present;
  std::string swapchainPresentMode;
  bool window = false;
  std::vector<std::string> saveFrames;
  RendererOptionSlots rendererOptions{};
  CLI::Option* csvOption = nullptr;
  CLI::Option* metaOption = nullptr;
  bool version = false;
};

template <std::size_t N>
std::vector<std::string> namesOf(const std::array<std::string_view, N>& names) {
  return {names.begin(), names.end()};
}

// Flags of the renderers whose schema row satisfies `chosen` ("--simd and --tbb-only").
template <std::predicate<const schema::RendererDefinition&> Chosen>
std::string flagsOf(Chosen chosen) {
  std::vector<std::string> flags;
  for (const auto& d : schema::kRendererDefinitions) {
    if (chosen(d)) flags.emplace_back(d.flag);
  }
  std::string text;
  for (std::size_t i = 0; i < flags.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == flags.size() ? " and " : ", ") + flags[i];
  }
  return text;
}

std::string flagsAccepting(RendererOption option) {
  return flagsOf([option](const schema::RendererDefinition& d) { return d.accepts(option); });
}

// The renderers of the SIMD kernel: the only ones with a traversal axis.
bool hasSimdKernel(RendererKind kind) { return definitionOf(kind).kernel == Kernel::simd; }

std::string simdKernelFlags() {
  return flagsOf([](const schema::RendererDefinition& d) { return d.kernel == Kernel::simd; });
}

// The renderers that fill Renderer::lastCounters(): the SIMD kernel's and
// the GPU renderer (schema frame_csv: the counter columns say what each counts).
bool counts(const schema::RendererDefinition& d) {
  return d.kernel == Kernel::simd || &d == &definitionOf(RendererKind::gpu);
}

std::string countingFlags() { return flagsOf(counts); }

std::string gpuFlag() { return std::string(definitionOf(RendererKind::gpu).flag); }

// The renderers of the thesis' half-precision experiment (docs/render-model.md
// section 10): the SIMD kernel's and the GPU renderer.
bool computesInHalf(const schema::RendererDefinition& d) {
  return d.kernel == Kernel::simd || &d == &definitionOf(RendererKind::gpu);
}
std::string gpuRtFlag() { return std::string(definitionOf(RendererKind::gpu_rt).flag); }

// The renderer options only mean something to the renderers whose schema
// row lists them; a run that recorded a setting its renderer ignored would
// mislabel its CSV rows. `--threads 1` is what a one-thread renderer does
// anyway, so it passes.
void checkRendererOptionsApply(RendererKind kind, const RendererOptionSlots& given, int threadCount) {
  const auto& definition = definitionOf(kind);
  for (std::size_t i = 0; i < given.size(); ++i) {
    const auto option = static_cast<RendererOption>(i);
    if (!*given[i] || definition.accepts(option)) continue;
    if (option == RendererOption::threads && threadCount == 1) continue;
    const std::string flag(schema::kRendererOptionFlags[i]);
    throw CLI::ValidationError(flag, "renderer " + std::string(nameOf(kind)) + " does not take " + flag + "; " + flag +
                                         " applies to " + flagsAccepting(option));
  }
}

// An output path: checked before the run, so that a long run does not fail
// at its end (an empty path or a directory found by the fuzz driver did).
void requireOutputPath(const std::filesystem::path& file, const std::string& option) {
  if (file.empty()) throw CLI::ValidationError(option, "empty output path");
  if (std::filesystem::is_directory(file)) {
    throw CLI::ValidationError(option, "'" + file.string() + "' is a directory, not a file");
  }
  const auto dir = file.parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir)) {
    throw CLI::ValidationError(option, "directory '" + dir.string() + "' does not exist");
  }
}

void addRendererChoice(CLI::App& app, RawOptions& raw) {
  for (std::size_t i = 0; i < raw.rendererFlags.size(); ++i) {
    app.add_flag(std::string(schema::kRendererDefinitions[i].flag), raw.rendererFlags[i],
                 "renderer " + std::string(schema::kRendererKindNames[i]));
  }
  app.add_option("scene", raw.scene, "scene file (JSON)")->capture_default_str();
}

void addFrameOptions(CLI::App& app, RunConfig& config) {
  app.add_option("--width", config.extent.width, "image width in pixels")->check(CLI::Range(1, 16384));
  app.add_option("--height", config.extent.height, "image height in pixels")->check(CLI::Range(1, 16384));
  app.add_option("--frames", config.measuredFrames, "measured frames (0 with --window: until the window is closed)")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--warmup", config.warmupFrames, "warm-up frames before the measured ones")
      ->check(CLI::Range(0, 1000000));
}

void addModelOptions(CLI::App& app, RawOptions& raw) {
  auto* algorithm = app.add_option("--algorithm", raw.algorithm, "single-pass|two-pass")
                        ->check(CLI::IsMember(namesOf(schema::kAlgorithmNames)));
  auto* exits = app.add_option("--early-exit", raw.earlyExit,
                               "none|all|comma list of " + joinNames(schema::kEarlyExitNames, ","));
  app.add_option("--accel", raw.accel,
                 "how a ray finds its nearest sphere: none (brute force, default)|bvh|auto (the BVH where its "
                 "estimated cost is under half of brute force's; the CSV records which ran)")
      ->check(CLI::IsMember(namesOf(schema::kAccelNames)));
  app.add_option("--stage", raw.stage, "the thesis' stages: original|single-pass|optimized (default)")
      ->check(CLI::IsMember(namesOf(schema::kStageNames)))
      ->excludes(algorithm)
      ->excludes(exits);
}

// A count that must be at least 1; CLI11's PositiveNumber would name a double's range.
CLI::Validator positiveInteger() {
  return {[](const std::string& text) {
            int value = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (ec == std::errc() && end == text.data() + text.size() && value >= 1) return std::string();
            return "expected a positive integer, got '" + text + "'";
          },
          "POSITIVE"};
}

void addTraversalOptions(CLI::App& app, RawOptions& raw) {
  app.add_option("--traversal", raw.traversal,
                 "how the SIMD kernel walks the BVH (" + simdKernelFlags() +
                     ", with --accel bvh): " + joinNames(schema::kTraversalNames, "|") + " (default " +
                     std::string(nameOf(RenderOptions{}.traversal)) + ")")
      ->check(CLI::IsMember(namesOf(schema::kTraversalNames)));
  raw.hybridThresholdOption =
      app.add_option("--hybrid-threshold", raw.hybridThreshold,
                     "with --traversal hybrid: a packet goes on as single rays where at most N of its lanes reach a "
                     "node (default: the kernel's, for its packet width)")
          ->check(positiveInteger())
          ->default_str("the kernel's");
  app.add_flag("--counters", raw.counters,
               countingFlags() +
                   ": count rays per bounce depth, BVH node visits, sphere tests and lane occupancy per frame (CSV "
                   "columns, metadata lane_counters)");
}

// The retired GPU variants' names that `flag` chose (schema:
// retired_gpu_variants), "persistent" or "a and b".
std::string retiredNamesOf(std::string_view flag) {
  std::string text;
  for (const auto& variant : schema::kRetiredGpuVariants) {
    if (variant.flag == flag) text += (text.empty() ? "" : " and ") + std::string(variant.name);
  }
  return text;
}

// The flags of the retired GPU variants stay known, hidden from --help, so
// that an old command line learns why it is refused and where the variants'
// measurements are, whichever value it gives (their default too: the GPU
// renderer has no other now).
void addRetiredGpuOptions(CLI::App& app) {
  for (const auto& variant : schema::kRetiredGpuVariants) {
    const std::string flag(variant.flag);
    if (app.get_option_no_throw(flag) != nullptr) continue;
    const std::string message = flag + " was retired: the GPU renderer always runs " + std::string(variant.kept) +
                                " now, so leave the option out; the measurements of the retired " +
                                retiredNamesOf(flag) + " are in " + std::string(variant.record);
    app.add_option_function<std::string>(
           flag, [flag, message](const std::string&) { throw CLI::ValidationError(flag, message); })
        ->group("");
  }
}

// The GPU renderers' variants (schema: gpu_bvhs, gpu_rt_reorders).
void addGpuOptions(CLI::App& app, RawOptions& raw) {
  const RenderOptions defaults;
  app.add_option("--gpu-bvh", raw.gpuBvh,
                 "which BVH the GPU renderer's shader walks (" + gpuFlag() + " with --accel bvh or auto): " +
                     joinNames(schema::kGpuBvhNames, "|") + " (default " + std::string(nameOf(defaults.gpuBvh)) +
                     "; auto with --accel auto: the fastest in a probe frame of each)")
      ->check(CLI::IsMember(namesOf(schema::kGpuBvhNames)));
  app.add_option("--gpu-rt-reorder", raw.gpuRtReorder,
                 "whether the ray-tracing pipeline renderer (" + gpuRtFlag() +
                     ") reorders its invocations by hit before shading (VK_NV_ray_tracing_invocation_reorder): " +
                     joinNames(schema::kGpuRtReorderNames, "|") + " (default " +
                     std::string(nameOf(defaults.gpuRtReorder)) + ")")
      ->check(CLI::IsMember(namesOf(schema::kGpuRtReorderNames)));
}

void addRendererOptions(CLI::App& app, RawOptions& raw, RunConfig& config) {
  const auto flag = [](RendererOption o) { return std::string(schema::kRendererOptionFlags[static_cast<int>(o)]); };
  const auto slot = [&](RendererOption o) -> CLI::Option*& { return raw.rendererOptions[static_cast<int>(o)]; };
  std::vector<std::string> lanes{"native"};
  for (int width : schema::kLaneWidths) lanes.push_back(std::to_string(width));
  slot(RendererOption::threads) =
      app.add_option(flag(RendererOption::threads), config.parallel.threads, "oneTBB threads")
          ->check(CLI::Range(1, 4096))
          ->default_str("all cores");
  std::string lanesHelp = "pixels per SIMD packet: native (the widest vector)";
  for (std::size_t i = 1; i < lanes.size(); ++i) lanesHelp += "|" + lanes[i];
  slot(RendererOption::lanes) =
      app.add_option(flag(RendererOption::lanes), raw.lanes, lanesHelp)->check(CLI::IsMember(lanes));
  slot(RendererOption::grain) =
      app.add_option(flag(RendererOption::grain), config.parallel.grain, "oneTBB grain size in rows")
          ->check(CLI::Range(1, 16384));
  raw.partition = nameOf(config.parallel.partition);
  slot(RendererOption::partition) =
      app.add_option(flag(RendererOption::partition), raw.partition, "oneTBB work split: rows|tiles (rows x 64 px)")
          ->check(CLI::IsMember(namesOf(schema::kPartitionNames)));
}

void addOutputOptions(CLI::App& app, RawOptions& raw) {
  raw.csvOption = app.add_option("--csv", raw.csv, "write one row per frame to this CSV file");
  raw.metaOption = app.add_option("--meta", raw.meta, "write the run's metadata here (default: CSV path .meta.json)");
  app.add_option("--save-frame", raw.saveFrames, "K:FILE.png: save animation frame K (0 = first warm-up frame)");
}

void addDeviceOptions(CLI::App& app, RawOptions& raw, RunConfig& config) {
  app.add_option("--present", raw.present,
                 joinNames(schema::kPresentModeNames, "|") +
                     ": where Present puts each frame (default: upload into the Vulkan device's present "
                     "image when a device opens, else none)")
      ->check(CLI::IsMember(namesOf(schema::kPresentModeNames)));
  app.add_option("--device", config.device,
                 "Vulkan device: INDEX or NAME-SUBSTRING (default: first discrete GPU, else integrated, else CPU)");
  app.add_flag("--list-devices", config.listDevices, "list the Vulkan devices and exit");
  app.add_flag("--window", raw.window,
               "show the frames in a window (--present window): GLFW + a Vulkan swapchain; Esc closes it");
  app.add_option("--present-mode", raw.swapchainPresentMode,
                 "with --window: the swapchain's present mode, " + joinNames(schema::kSwapchainPresentModeNames, "|") +
                     " (default fifo: one frame per display refresh)")
      ->check(CLI::IsMember(namesOf(schema::kSwapchainPresentModeNames)));
  app.add_flag("--vk-validation", config.vkValidation,
               "enable VK_LAYER_KHRONOS_validation; any warning or error fails the run (exit 1)");
}

void addRunOptions(CLI::App& app, RawOptions& raw, RunConfig& config) {
  app.add_option("--precision", raw.precision,
                 "the type of the render model's arithmetic: " + joinNames(schema::kPrecisionNames, "|") +
                     " (default f32); f16, the thesis' half-precision experiment, for " + flagsOf(computesInHalf) +
                     " where the CPU's SIMD target or the Vulkan device computes in f16")
      ->check(CLI::IsMember(namesOf(schema::kPrecisionNames)));
  app.add_flag("--agreement", config.agreement,
               "after the frames, compare frame 0 with the double-precision reference (metadata agreement: share "
               "within 2/255, PSNR)");
  app.add_flag("--quiet,-q", config.quiet, "print nothing but errors");
  app.add_flag("--tracy-wait", config.tracyWait,
               "wait for a Tracy viewer (127.0.0.1, port TRACY_PORT or 8086) before the first frame");
  app.add_flag("--version", raw.version, "print the version and exit");
}

void applyRendererChoice(const RawOptions& raw, RunConfig& config) {
  const auto chosen = std::ranges::count(raw.rendererFlags, true);
  if (chosen > 1) throw CLI::ValidationError("renderer", "choose one of the renderer flags");
  if (chosen == 1) {
    config.renderer = static_cast<RendererKind>(std::ranges::find(raw.rendererFlags, true) - raw.rendererFlags.begin());
  }
  config.scenePath = raw.scene;
  checkRendererOptionsApply(config.renderer, raw.rendererOptions, config.parallel.threads);
  config.parallel.lanes = raw.lanes == "native" ? ParallelSettings::kNativeLanes : std::stoi(raw.lanes);
  config.parallel.partition = *enumByName<Partition>(schema::kPartitionNames, raw.partition);
#ifndef TRACY_ENABLE
  if (config.tracyWait) {
    throw CLI::ValidationError("--tracy-wait", "this build has no Tracy client (use the 'profile' preset)");
  }
#endif
}

void applyModelOptions(const RawOptions& raw, RunConfig& config) {
  config.options = optionsForStage(Stage::optimized);
  if (!raw.stage.empty()) config.options = optionsForStage(*enumByName<Stage>(schema::kStageNames, raw.stage));
  if (!raw.algorithm.empty()) config.options.algorithm = *enumByName<Algorithm>(schema::kAlgorithmNames, raw.algorithm);
  if (!raw.earlyExit.empty()) config.options.earlyExits = parseEarlyExits(raw.earlyExit);
  if (!raw.accel.empty()) config.options.accel = *enumByName<Accel>(schema::kAccelNames, raw.accel);
  if (const auto own = definitionOf(config.renderer).ownAccel) {
    if (!raw.accel.empty() && config.options.accel != *own) {
      throw CLI::ValidationError("--accel", "renderer " + std::string(nameOf(config.renderer)) +
                                                " always uses its own " + std::string(nameOf(*own)) + "; --accel " +
                                                raw.accel + " does not apply");
    }
    config.options.accel = *own;
  }
  if (!raw.present.empty()) config.present = *enumByName<PresentMode>(schema::kPresentModeNames, raw.present);
}

// The traversal axis belongs to the SIMD kernel alone (schema: traversals),
// the counters to it and the GPU renderer (frame_csv's counter columns); a
// run of another renderer would record a setting it ignored. Runs after
// applyModelOptions, which resets config.options to the stage's.
void applyTraversalOptions(const RawOptions& raw, RunConfig& config) {
  const std::string renderer(nameOf(config.renderer));
  if (!raw.traversal.empty()) {
    config.options.traversal = *enumByName<Traversal>(schema::kTraversalNames, raw.traversal);
  }
  if (config.options.traversal != Traversal::packet) {
    if (!hasSimdKernel(config.renderer)) {
      throw CLI::ValidationError("--traversal", "--traversal " + raw.traversal + " applies to the SIMD renderers (" +
                                                    simdKernelFlags() + ") with --accel bvh; renderer " + renderer +
                                                    " has no traversal");
    }
    if (config.options.accel == Accel::none) {
      throw CLI::ValidationError("--traversal", "--traversal " + raw.traversal +
                                                    " walks a BVH: it needs --accel bvh or auto (accel is " +
                                                    std::string(nameOf(config.options.accel)) + ")");
    }
  }
  if (*raw.hybridThresholdOption) {
    if (config.options.traversal != Traversal::hybrid) {
      throw CLI::ValidationError("--hybrid-threshold", "--hybrid-threshold needs --traversal hybrid");
    }
    config.options.hybridThreshold = raw.hybridThreshold;
  }
  if (raw.counters && !counts(definitionOf(config.renderer))) {
    throw CLI::ValidationError("--counters", "only the SIMD renderers and the GPU renderer (" + countingFlags() +
                                                 ") count; renderer " + renderer + " does not");
  }
  config.options.counters = raw.counters;
}

// The GPU renderer's walk (schema: gpu_bvhs) means nothing to the other
// renderers, nor without a BVH; as for --traversal, a run would record a
// setting it ignored. It is refused there whenever it is given, its default
// value too. Runs after applyModelOptions (config.options.accel).
void applyGpuOptions(const RawOptions& raw, RunConfig& config) {
  if (!raw.gpuBvh.empty() && config.renderer != RendererKind::gpu) {
    throw CLI::ValidationError("--gpu-bvh", "--gpu-bvh applies to the GPU renderer (" + gpuFlag() +
                                                ") only; renderer " + std::string(nameOf(config.renderer)) +
                                                " does not take it");
  }
  if (!raw.gpuBvh.empty()) {
    if (config.options.accel == Accel::none) {
      const std::string accel(nameOf(config.options.accel));
      throw CLI::ValidationError("--gpu-bvh", "--gpu-bvh " + raw.gpuBvh +
                                                  " chooses the BVH the shader walks: it needs --accel bvh or auto "
                                                  "(accel is " +
                                                  accel + ")");
    }
    config.options.gpuBvh = *enumByName<GpuBvh>(schema::kGpuBvhNames, raw.gpuBvh);
  } else if (config.renderer == RendererKind::gpu && config.options.accel == Accel::auto_) {
    config.options.gpuBvh = GpuBvh::auto_;  // --accel auto chooses the walk too (schema: gpu_bvhs)
  }
  if (!raw.gpuRtReorder.empty()) {
    if (config.renderer != RendererKind::gpu_rt) {
      throw CLI::ValidationError("--gpu-rt-reorder", "--gpu-rt-reorder applies to the ray-tracing pipeline renderer (" +
                                                         gpuRtFlag() + ") only; renderer " +
                                                         std::string(nameOf(config.renderer)) + " does not take it");
    }
    config.options.gpuRtReorder = *enumByName<GpuRtReorder>(schema::kGpuRtReorderNames, raw.gpuRtReorder);
  }
}

// f32 is what every renderer computes in; f16 only the renderers of the
// experiment take, and they refuse it where the hardware lacks f16 arithmetic.
void applyPrecision(const RawOptions& raw, RunConfig& config) {
  if (raw.precision.empty()) return;
  config.options.precision = *enumByName<Precision>(schema::kPrecisionNames, raw.precision);
  if (config.options.precision != Precision::f32 && !computesInHalf(definitionOf(config.renderer))) {
    throw CLI::ValidationError("--precision", "--precision " + raw.precision + " applies to " +
                                                  flagsOf(computesInHalf) + "; renderer " +
                                                  std::string(nameOf(config.renderer)) + " computes in f32 only");
  }
}

void applyWindowOptions(const RawOptions& raw, RunConfig& config) {
  if (raw.window) {
    if (config.present && config.present != PresentMode::window) {
      throw CLI::ValidationError("--window", "--window presents into the window; it excludes --present " + raw.present);
    }
    config.present = PresentMode::window;
  }
  if (config.windowed() && !RT_WINDOW) {
    throw CLI::ValidationError("--window",
                               "this build has no window (configure with -DRT_WINDOW=ON; Debian: libglfw3-dev)");
  }
  if (!raw.swapchainPresentMode.empty()) {
    if (!config.windowed()) throw CLI::ValidationError("--present-mode", "--present-mode needs --window");
    config.swapchainPresentMode =
        *enumByName<schema::SwapchainPresentMode>(schema::kSwapchainPresentModeNames, raw.swapchainPresentMode);
  }
  if (config.measuredFrames == 0 && !config.windowed()) {
    throw CLI::ValidationError("--frames", "--frames 0 (run until the window is closed) needs --window");
  }
}

void applyOutputs(const RawOptions& raw, RunConfig& config) {
  if (*raw.csvOption) {
    config.csvPath = raw.csv;
    requireOutputPath(raw.csv, "--csv");
  }
  if (*raw.metaOption) {
    config.metaPath = raw.meta;
    requireOutputPath(raw.meta, "--meta");
  }
  for (const auto& text : raw.saveFrames) {
    SaveFrameRequest request = parseSaveFrame(text);
    if (!config.untilClosed() && request.frame >= config.totalFrames()) {
      throw CLI::ValidationError("--save-frame", "frame " + std::to_string(request.frame) +
                                                     " is past the last frame (" +
                                                     std::to_string(config.totalFrames() - 1) + ")");
    }
    requireOutputPath(request.file, "--save-frame");
    config.saveFrames.push_back(std::move(request));
  }
}

// "GLFW 3.3.8" from the library versions ("...,glfw=3.3.8,..."), in RT_WINDOW builds.
std::string windowLibraryText(std::string_view libraryVersions) {
  if (!RT_WINDOW) return "not built in";
  const auto at = libraryVersions.find("glfw=");
  if (at == std::string_view::npos) return "GLFW";
  const auto version = libraryVersions.substr(at + 5);
  return "GLFW " + std::string(version.substr(0, version.find(',')));
}

}  // namespace

std::variant<RunConfig, CliExit> parseCommandLine(int argc, const char* const* argv) {
  RunConfig config;
  config.commandLine.assign(argv, argv + argc);
  RawOptions raw;
  raw.scene = config.scenePath.string();

  CLI::App app("Ray tracer of sphere scenes with interchangeable renderers; times every frame.", "raytracer");
  app.option_defaults()->always_capture_default();
  addRendererChoice(app, raw);
  addFrameOptions(app, config);
  addModelOptions(app, raw);
  addTraversalOptions(app, raw);
  addGpuOptions(app, raw);
  addRetiredGpuOptions(app);
  addRendererOptions(app, raw, config);
  addOutputOptions(app, raw);
  addDeviceOptions(app, raw, config);
  addRunOptions(app, raw, config);

  try {
    app.parse(argc, argv);
    if (raw.version) return CliExit{0, versionText(), ""};
    applyRendererChoice(raw, config);
    applyModelOptions(raw, config);
    applyTraversalOptions(raw, config);
    applyGpuOptions(raw, config);
    applyPrecision(raw, config);
    applyWindowOptions(raw, config);
    applyOutputs(raw, config);
  } catch (const CLI::CallForHelp&) {
    return CliExit{0, app.help(), ""};
  } catch (const CLI::ParseError& e) {
    // The message goes last, after the usage: whoever keeps only the tail
    // of stderr (the bench runner) or its last line still sees the reason.
    return CliExit{kExitBadInput, "", app.help() + "\nraytracer: " + e.what() + "\n"};
  }
  return config;
}

std::string versionText() {
  const BuildInfo& b = buildInfo();
  std::ostringstream out;
  out << "raytracer " << b.version << " (commit " << b.gitCommit << (b.gitDirty ? ", dirty" : "") << ", " << b.buildType
      << ", " << b.compiler << ")\n"
      << "Tracy client: " << (b.tracyClient.empty() ? "not built in" : b.tracyClient) << "\n"
      << "Window (--window): " << windowLibraryText(b.libraryVersions) << "\n";
  return out.str();
}

}  // namespace rt
