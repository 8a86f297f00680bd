#include "app/cli.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <charconv>
#include <sstream>

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

bool usesTbb(RendererKind kind) { return kind == RendererKind::simd_tbb || kind == RendererKind::tbb_only; }
bool usesSimd(RendererKind kind) { return kind == RendererKind::simd_tbb || kind == RendererKind::simd_only; }

// The parallel options only mean something to some renderers; a run that
// records a setting its renderer ignored would mislabel its CSV rows.
void checkParallelOptionsApply(RendererKind kind, const CLI::Option& threads, const CLI::Option& lanes,
                               const CLI::Option& grain, const CLI::Option& partition, int threadCount) {
  const std::string renderer(nameOf(kind));
  if (threads && !usesTbb(kind) && threadCount != 1) {
    throw CLI::ValidationError("--threads", "renderer " + renderer + " runs on one thread; --threads applies to --simd and --tbb-only");
  }
  if (lanes && !usesSimd(kind)) {
    throw CLI::ValidationError("--lanes", "renderer " + renderer + " has no SIMD packets; --lanes applies to --simd and --simd-only");
  }
  for (const CLI::Option* option : {&grain, &partition}) {
    if (*option && !usesTbb(kind)) {
      throw CLI::ValidationError(option->get_name(), "renderer " + renderer + " does not use oneTBB; " +
                                                         option->get_name() + " applies to --simd and --tbb-only");
    }
  }
}

void requireExistingDirectory(const std::filesystem::path& file, const std::string& option) {
  const auto dir = file.parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir)) {
    throw CLI::ValidationError(option, "directory '" + dir.string() + "' does not exist");
  }
}

}  // namespace

std::string versionText() {
  const BuildInfo& b = buildInfo();
  std::ostringstream out;
  out << "raytracer " << b.version << " (commit " << b.gitCommit << (b.gitDirty ? ", dirty" : "") << ", "
      << b.buildType << ", " << b.compiler << ")\n"
      << "Tracy client: " << (b.tracyClient.empty() ? "not built in" : b.tracyClient) << "\n";
  return out.str();
}

std::variant<RunConfig, CliExit> parseCommandLine(int argc, const char* const* argv) {
  RunConfig config;
  config.commandLine.assign(argv, argv + argc);

  CLI::App app("Ray tracer of sphere scenes with interchangeable renderers; times every frame.", "raytracer");
  app.option_defaults()->always_capture_default();

  std::array<bool, schema::kRendererKindNames.size()> rendererFlags{};
  for (std::size_t i = 0; i < rendererFlags.size(); ++i) {
    app.add_flag(std::string(schema::kRendererFlags[i]), rendererFlags[i],
                 "renderer " + std::string(schema::kRendererKindNames[i]));
  }
  std::string scene = config.scenePath.string();
  app.add_option("scene", scene, "scene file (JSON)")->capture_default_str();
  app.add_option("--width", config.extent.width, "image width in pixels")->check(CLI::Range(1, 16384));
  app.add_option("--height", config.extent.height, "image height in pixels")->check(CLI::Range(1, 16384));
  app.add_option("--frames", config.measuredFrames, "measured frames")->check(CLI::Range(1, 1000000));
  app.add_option("--warmup", config.warmupFrames, "warm-up frames before the measured ones")
      ->check(CLI::Range(0, 1000000));
  std::string algorithm, earlyExit, stage;
  auto* algorithmOpt = app.add_option("--algorithm", algorithm, "single-pass|two-pass")
                           ->check(CLI::IsMember(std::vector<std::string>(schema::kAlgorithmNames.begin(),
                                                                          schema::kAlgorithmNames.end())));
  auto* exitOpt = app.add_option("--early-exit", earlyExit,
                                 "none|all|comma list of " + joinNames(schema::kEarlyExitNames, ","));
  auto* stageOpt = app.add_option("--stage", stage, "the thesis' stages: original|single-pass|optimized (default)")
                       ->check(CLI::IsMember(std::vector<std::string>(schema::kStageNames.begin(),
                                                                      schema::kStageNames.end())));
  stageOpt->excludes(algorithmOpt)->excludes(exitOpt);
  auto* threadsOpt = app.add_option("--threads", config.parallel.threads, "oneTBB threads")
                         ->check(CLI::Range(1, 4096))
                         ->default_str("all cores");
  std::string lanes = "native";
  auto* lanesOpt = app.add_option("--lanes", lanes, "pixels per SIMD packet: native (widest vector)|4|8|16")
                       ->check(CLI::IsMember({"native", "4", "8", "16"}));
  auto* grainOpt = app.add_option("--grain", config.parallel.grain, "oneTBB grain size in rows")
                       ->check(CLI::Range(1, 16384));
  std::string partition(nameOf(config.parallel.partition));
  auto* partitionOpt = app.add_option("--partition", partition, "oneTBB work split: rows|tiles (rows x 64 px)")
                           ->check(CLI::IsMember(std::vector<std::string>(schema::kPartitionNames.begin(),
                                                                          schema::kPartitionNames.end())));
  std::string csv, meta;
  auto* csvOpt = app.add_option("--csv", csv, "write one row per frame to this CSV file");
  auto* metaOpt = app.add_option("--meta", meta, "write the run's metadata here (default: CSV path .meta.json)");
  std::vector<std::string> saveFrames;
  app.add_option("--save-frame", saveFrames, "K:FILE.png: save animation frame K (0 = first warm-up frame)");
  std::string present;
  app.add_option("--present", present,
                 "none|upload: where Present puts each frame (default: upload into the Vulkan device's present "
                 "image when a device opens, else none)")
      ->check(CLI::IsMember(std::vector<std::string>(schema::kPresentModeNames.begin(), schema::kPresentModeNames.end())));
  app.add_option("--device", config.device,
                 "Vulkan device: INDEX or NAME-SUBSTRING (default: first discrete GPU, else integrated, else CPU)");
  app.add_flag("--list-devices", config.listDevices, "list the Vulkan devices and exit");
  app.add_flag("--vk-validation", config.vkValidation,
               "enable VK_LAYER_KHRONOS_validation; any warning or error fails the run (exit 1)");
  app.add_flag("--quiet,-q", config.quiet, "print nothing but errors");
  app.add_flag("--tracy-wait", config.tracyWait,
               "wait for a Tracy viewer (127.0.0.1, port TRACY_PORT or 8086) before the first frame");
  bool version = false;
  app.add_flag("--version", version, "print the version and exit");

  try {
    app.parse(argc, argv);
    if (version) return CliExit{0, versionText(), ""};

    const auto chosen = std::ranges::count(rendererFlags, true);
    if (chosen > 1) throw CLI::ValidationError("renderer", "choose one of the renderer flags");
    if (chosen == 1) config.renderer = static_cast<RendererKind>(std::ranges::find(rendererFlags, true) - rendererFlags.begin());
    config.scenePath = scene;
    checkParallelOptionsApply(config.renderer, *threadsOpt, *lanesOpt, *grainOpt, *partitionOpt, config.parallel.threads);
    config.parallel.lanes = lanes == "native" ? ParallelSettings::kNativeLanes : std::stoi(lanes);
    config.parallel.partition = *enumByName<Partition>(schema::kPartitionNames, partition);
#ifndef TRACY_ENABLE
    if (config.tracyWait) {
      throw CLI::ValidationError("--tracy-wait", "this build has no Tracy client (use the 'profile' preset)");
    }
#endif

    config.options = optionsForStage(Stage::optimized);
    if (!stage.empty()) config.options = optionsForStage(*enumByName<Stage>(schema::kStageNames, stage));
    if (!algorithm.empty()) config.options.algorithm = *enumByName<Algorithm>(schema::kAlgorithmNames, algorithm);
    if (!earlyExit.empty()) config.options.earlyExits = parseEarlyExits(earlyExit);
    if (!present.empty()) config.present = *enumByName<PresentMode>(schema::kPresentModeNames, present);

    if (*csvOpt) {
      config.csvPath = csv;
      requireExistingDirectory(csv, "--csv");
    }
    if (*metaOpt) {
      config.metaPath = meta;
      requireExistingDirectory(meta, "--meta");
    }
    for (const auto& text : saveFrames) {
      SaveFrameRequest request = parseSaveFrame(text);
      if (request.frame >= config.totalFrames()) {
        throw CLI::ValidationError("--save-frame", "frame " + std::to_string(request.frame) +
                                                       " is past the last frame (" +
                                                       std::to_string(config.totalFrames() - 1) + ")");
      }
      requireExistingDirectory(request.file, "--save-frame");
      config.saveFrames.push_back(std::move(request));
    }
  } catch (const CLI::CallForHelp&) {
    return CliExit{0, app.help(), ""};
  } catch (const CLI::ParseError& e) {
    // The message goes last, after the usage: whoever keeps only the tail
    // of stderr (the bench runner) or its last line still sees the reason.
    return CliExit{kExitBadInput, "", app.help() + "\nraytracer: " + e.what() + "\n"};
  }
  return config;
}

}  // namespace rt
