#include "app/cli.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <charconv>
#include <concepts>
#include <ranges>
#include <sstream>
#include <utility>

#include "app/build_info.h"
#include "app/render_axes.h"

namespace rt {
namespace {

template <typename Enum, std::size_t N>
std::optional<Enum> enumByName(const std::array<std::string_view, N>& names, std::string_view name) {
  const auto it = std::ranges::find(names, name);
  if (it == names.end()) return std::nullopt;
  return static_cast<Enum>(it - names.begin());
}

template <std::ranges::input_range Names>
std::string joinNames(const Names& names, std::string_view separator) {
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

// One axis of the schema (schema: axes) as the command line gives it: a
// choice's name, a count or a toggle, by its kind; `option` says whether it was given.
struct AxisInput {
  std::string choice;
  int count = 0;
  bool toggle = false;
  CLI::Option* option = nullptr;
};

// What CLI11 parses into text first; converted and checked after parsing.
struct RawOptions {
  std::array<bool, schema::kRendererKindNames.size()> rendererFlags{};
  std::string scene;
  std::string algorithm, earlyExit, stage;
  std::array<AxisInput, schema::kAxisDefinitions.size()> axes{};
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

// Flags of the renderers that satisfy `chosen` ("--simd and --tbb-only").
template <std::predicate<RendererKind> Chosen>
std::string flagsOf(Chosen chosen) {
  std::vector<std::string> flags;
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    if (chosen(static_cast<RendererKind>(i))) flags.emplace_back(schema::kRendererDefinitions[i].flag);
  }
  std::string text;
  for (std::size_t i = 0; i < flags.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == flags.size() ? " and " : ", ") + flags[i];
  }
  return text;
}

std::string flagsAccepting(RendererOption option) {
  return flagsOf([option](RendererKind kind) { return definitionOf(kind).accepts(option); });
}

// The flags of the renderers that take an axis ("--simd and --simd-only").
std::string flagsTaking(const AxisDefinition& axis) {
  return flagsOf([&axis](RendererKind kind) { return axis.takenBy(kind); });
}

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
  app.add_option("--stage", raw.stage, "the thesis' stages: original|single-pass|optimized (default)")
      ->check(CLI::IsMember(namesOf(schema::kStageNames)))
      ->excludes(algorithm)
      ->excludes(exits);
}

// A count of at least `minimum`; CLI11's PositiveNumber would name a double's range.
CLI::Validator integerAtLeast(int minimum) {
  const std::string expected = minimum == 1 ? "a positive integer" : "an integer >= " + std::to_string(minimum);
  return {[minimum, expected](const std::string& text) {
            int value = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (ec == std::errc() && end == text.data() + text.size() && value >= minimum) return std::string();
            return "expected " + expected + ", got '" + text + "'";
          },
          "N"};
}

// The names of an axis' values in `mask` (bits over its values): "bvh or auto".
std::string valuesIn(const AxisDefinition& d, unsigned mask, std::string_view separator) {
  std::vector<std::string_view> chosen;
  for (std::size_t i = 0; i < d.values.size(); ++i) {
    if (((mask >> i) & 1u) != 0) chosen.push_back(d.values[i]);
  }
  return joinNames(chosen, separator);
}

// A value of an axis in words: a choice's name, a count's number, nothing for a toggle.
std::string valueText(Axis axis, int value) {
  const auto& d = definitionOf(axis);
  if (d.kind == AxisKind::choice) return std::string(d.values[static_cast<std::size_t>(value)]);
  return d.kind == AxisKind::count ? std::to_string(value) : std::string();
}

// The axis with a value as a command line gives it: "--traversal single", "--counters".
std::string givenText(Axis axis, int value) {
  const std::string text = valueText(axis, value);
  return std::string(definitionOf(axis).flag) + (text.empty() ? "" : " " + text);
}

bool takenByEveryRenderer(const AxisDefinition& d) {
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
    if (!d.takenBy(static_cast<RendererKind>(i))) return false;
  }
  return true;
}

// Where an axis applies, for --help: "; for --simd and --simd-only, with --accel bvh|auto".
std::string axisScope(Axis axis) {
  const auto& d = definitionOf(axis);
  std::string scope;
  if (!takenByEveryRenderer(d)) {
    const std::string values = d.defaultForAll ? valuesIn(d, ~(1u << d.defaultValue), "|") + " " : "";
    scope = "; " + values + "for " + flagsTaking(d);
  }
  for (const auto& r : schema::kAxisRequirements) {
    if (r.axis != axis) continue;
    const auto& on = definitionOf(r.on);
    scope += ", with " + std::string(on.flag) + " " + valuesIn(on, r.valueMask, "|");
  }
  return scope;
}

// An axis' --help text from its declaration: its values, what it does, its
// default (and those that another axis' value sets), where it applies.
std::string axisHelp(Axis axis) {
  const auto& d = definitionOf(axis);
  if (d.kind != AxisKind::choice) return std::string(d.description) + axisScope(axis);
  std::string help =
      joinNames(d.values, "|") + ": " + std::string(d.description) + " (default " + valueText(axis, d.defaultValue);
  for (const auto& c : schema::kAxisConditionalDefaults) {
    if (c.axis == axis) help += "; " + valueText(axis, c.value) + " with " + givenText(c.on, c.onValue);
  }
  return help + ")" + axisScope(axis);
}

// One option per axis of the schema (schema: axes), by its kind.
void addAxisOptions(CLI::App& app, RawOptions& raw) {
  for (std::size_t i = 0; i < raw.axes.size(); ++i) {
    const auto axis = static_cast<Axis>(i);
    const auto& d = definitionOf(axis);
    const std::string flag(d.flag);
    AxisInput& input = raw.axes[i];
    if (d.kind == AxisKind::choice) {
      input.option = app.add_option(flag, input.choice, axisHelp(axis))
                         ->check(CLI::IsMember(std::vector<std::string>(d.values.begin(), d.values.end())));
    } else if (d.kind == AxisKind::count) {
      // A default below the minimum is the renderer's own choice, which the help text names.
      input.option = app.add_option(flag, input.count, axisHelp(axis))
                         ->check(integerAtLeast(d.minimum))
                         ->default_str(d.defaultValue < d.minimum ? "" : std::to_string(d.defaultValue));
    } else {
      input.option = app.add_flag(flag, input.toggle, axisHelp(axis));
    }
  }
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
  if (!raw.present.empty()) config.present = *enumByName<PresentMode>(schema::kPresentModeNames, raw.present);
}

int givenValue(Axis axis, const AxisInput& input) {
  const auto& d = definitionOf(axis);
  if (d.kind == AxisKind::choice) return static_cast<int>(std::ranges::find(d.values, input.choice) - d.values.begin());
  return d.kind == AxisKind::count ? input.count : static_cast<int>(input.toggle);
}

// A renderer takes an axis where the schema lists it (axes[].renderers), or
// the axis' default where every renderer has that (default_for_all). A run
// that recorded a setting its renderer ignored would mislabel its CSV rows,
// so any other is refused, the axis' default value too.
void checkRendererTakes(Axis axis, int value, RendererKind kind) {
  const auto& d = definitionOf(axis);
  if (d.takenBy(kind) || (d.defaultForAll && value == d.defaultValue)) return;
  const std::string what = d.defaultForAll ? givenText(axis, value) : std::string(d.flag);
  throw CLI::ValidationError(std::string(d.flag), "renderer " + std::string(nameOf(kind)) + " does not take " + what +
                                                      "; " + what + " applies to " + flagsTaking(d));
}

// What a given axis needs of an earlier one (axes[].requires), as that one was set.
void checkRequirements(Axis axis, int value, const RenderOptions& options) {
  for (const auto& r : schema::kAxisRequirements) {
    const int current = axisValue(options, r.on);
    if (r.axis != axis || ((r.valueMask >> current) & 1u) != 0) continue;
    const auto& on = definitionOf(r.on);
    throw CLI::ValidationError(std::string(definitionOf(axis).flag),
                               givenText(axis, value) + " needs " + std::string(on.flag) + " " +
                                   valuesIn(on, r.valueMask, " or ") + " (" + std::string(nameOf(r.on)) + " is " +
                                   valueText(r.on, current) + ")");
  }
}

// The value a renderer always has, whatever the command line says: its own
// structure (schema renderers[].own_accel: Embree's BVH, the driver's for gpu_rt).
std::optional<int> ownValue(RendererKind kind, Axis axis) {
  const auto own = definitionOf(kind).ownAccel;
  if (axis != Axis::accel || !own) return std::nullopt;
  return static_cast<int>(*own);
}

// The default that another axis' value sets (axes[].default_when: --gpu-bvh
// auto with --accel auto), where the renderer takes the axis.
std::optional<int> conditionalDefault(Axis axis, const RenderOptions& options) {
  for (const auto& c : schema::kAxisConditionalDefaults) {
    if (c.axis == axis && axisValue(options, c.on) == c.onValue) return c.value;
  }
  return std::nullopt;
}

// Every axis of the schema (schema: axes) through one path, in schema
// order, so that a requirement reads the value its earlier axis settled on.
// Runs after applyModelOptions, which resets config.options to the stage's.
void applyAxes(const RawOptions& raw, RunConfig& config) {
  for (std::size_t i = 0; i < raw.axes.size(); ++i) {
    const auto axis = static_cast<Axis>(i);
    const bool given = raw.axes[i].option->count() > 0;
    std::optional<int> value;
    if (given) {
      value = givenValue(axis, raw.axes[i]);
      checkRendererTakes(axis, *value, config.renderer);
      checkRequirements(axis, *value, config.options);
    } else if (definitionOf(axis).takenBy(config.renderer)) {
      value = conditionalDefault(axis, config.options);
    }
    if (const auto own = ownValue(config.renderer, axis)) {
      if (given && *value != *own) {
        throw CLI::ValidationError(std::string(definitionOf(axis).flag),
                                   "renderer " + std::string(nameOf(config.renderer)) + " always uses its own " +
                                       valueText(axis, *own) + "; " + givenText(axis, *value) + " does not apply");
      }
      value = own;
    }
    if (value) setAxisValue(config.options, axis, *value);
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
  addAxisOptions(app, raw);
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
    applyAxes(raw, config);
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
