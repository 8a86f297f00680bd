#include "app/run_metadata.h"

#include <sys/utsname.h>

#include <cmath>
#include <concepts>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "app/build_info.h"
#include "core/sha256.h"
#include "render/cpu_renderers.h"
#include "rt_schema_metadata.h"

namespace rt {
namespace {

using schema::RunMetadataKey;

std::string firstValueOf(const std::filesystem::path& file, std::string_view key, char separator) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) != 0) continue;
    const auto sep = line.find(separator);
    if (sep == std::string::npos) continue;
    std::string value = line.substr(sep + 1);
    const auto first = value.find_first_not_of(" \t\"");
    const auto last = value.find_last_not_of(" \t\"");
    return first == std::string::npos ? "" : value.substr(first, last - first + 1);
  }
  return "";
}

// An object with exactly the keys the schema lists for it (the generated
// enum `Key`), each valued by `valueOf`: a schema key without a case in
// `valueOf` is a -Wswitch warning here, and the binary's sidecars are
// checked against the schema in tests/app/test_raytracer_cli.py.
template <typename Key, std::size_t N, std::invocable<Key> ValueOf>
nlohmann::json objectOf(const std::array<std::string_view, N>& keyNames, ValueOf valueOf) {
  nlohmann::json object = nlohmann::json::object();
  for (std::size_t i = 0; i < N; ++i) object[std::string(keyNames[i])] = valueOf(static_cast<Key>(i));
  return object;
}

// A part of the run that it may lack (a BVH, --counters, --agreement, a
// device, a window): null without it, else `toJson` of it.
template <typename Part, std::invocable<const Part&> ToJson>
nlohmann::json orNull(const std::optional<Part>& part, ToJson toJson) {
  return part ? toJson(*part) : nlohmann::json(nullptr);
}

[[noreturn]] void unhandledKey(std::string_view object) {
  throw std::logic_error("unhandled key of the metadata's " + std::string(object) + " object");
}

std::string fileText(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The architecture this binary was compiled for, named as uname names it.
constexpr std::string_view kBinaryArchitecture =
#if defined(__x86_64__)
    "x86_64";
#elif defined(__aarch64__)
    "aarch64";
#else
    "other";
#endif

// The architecture /proc/cpuinfo describes, from keys only one of them uses.
std::string_view cpuinfoArchitecture(std::string_view cpuinfo) {
  if (cpuinfo.find("vendor_id") != std::string_view::npos) return "x86_64";
  if (cpuinfo.find("CPU implementer") != std::string_view::npos) return "aarch64";
  return "unknown";
}

nlohmann::json emulationJson(const std::optional<Emulation>& emulation) {
  if (!emulation) return nullptr;
  using Key = schema::MetadataHostEmulationKey;
  return objectOf<Key>(schema::kMetadataHostEmulationKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::emulator: return emulation->emulator;
      case Key::cpu: return emulation->cpu ? nlohmann::json(*emulation->cpu) : nlohmann::json(nullptr);
      case Key::host_architecture: return emulation->hostArchitecture;
    }
    unhandledKey("host.emulation");
  });
}

nlohmann::json hostInfo() {
  std::string cpu = firstValueOf("/proc/cpuinfo", "model name", ':');
  if (cpu.empty()) cpu = "unknown";
  std::string os = firstValueOf("/etc/os-release", "PRETTY_NAME", '=');
  utsname u{};
  std::string kernel = "unknown";
  if (::uname(&u) == 0) {
    kernel = std::string(u.sysname) + " " + u.release + " " + u.machine;
    if (os.empty()) os = u.sysname;
  }
  using Key = schema::MetadataHostKey;
  return objectOf<Key>(schema::kMetadataHostKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::cpu_model: return cpu;
      case Key::logical_cores: return std::thread::hardware_concurrency();
      case Key::os: return os;
      case Key::kernel: return kernel;
      case Key::emulation: {
        std::string processName = fileText("/proc/self/comm");
        while (!processName.empty() && processName.back() == '\n') processName.pop_back();
        const char* qemuCpu = std::getenv("QEMU_CPU");
        return emulationJson(emulationOf(processName, fileText("/proc/cpuinfo"), qemuCpu != nullptr ? qemuCpu : ""));
      }
    }
    unhandledKey("host");
  });
}

nlohmann::json libraryVersions() {
  nlohmann::json libs = nlohmann::json::object();
  std::stringstream list{std::string(buildInfo().libraryVersions)};
  std::string item;
  while (std::getline(list, item, ',')) {
    const auto eq = item.find('=');
    if (eq != std::string::npos) libs[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return libs;
}

// The Nix flake's package and apps set RT_NIX=1 and RT_NIXPKGS_REV (the
// nixpkgs revision that fixed compiler and libraries); null elsewhere.
nlohmann::json nixJson() {
  const char* nix = std::getenv("RT_NIX");
  if (nix == nullptr || std::string_view(nix) != "1") return nullptr;
  const char* rev = std::getenv("RT_NIXPKGS_REV");
  const std::string revision = rev != nullptr && *rev != '\0' ? rev : "unknown";
  using Key = schema::MetadataBuildNixKey;
  return objectOf<Key>(schema::kMetadataBuildNixKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::nixpkgs_rev: return revision;
    }
    unhandledKey("build.nix");
  });
}

nlohmann::json simdTargetsJson() {
  using Key = schema::MetadataBuildSimdTargetsKey;
  nlohmann::json targets = nlohmann::json::array();
  for (const SimdBuildTarget& target : simdBuildTargets()) {
    targets.push_back(objectOf<Key>(schema::kMetadataBuildSimdTargetsKeyNames, [&](Key key) -> nlohmann::json {
      switch (key) {
        case Key::name: return target.name;
        case Key::f16: return target.halfPrecision;
      }
      unhandledKey("build.simd_targets");
    }));
  }
  return targets;
}

nlohmann::json buildJson() {
  const BuildInfo& b = buildInfo();
  using Key = schema::MetadataBuildKey;
  return objectOf<Key>(schema::kMetadataBuildKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::version: return b.version;
      case Key::git_commit: return b.gitCommit;
      case Key::git_dirty: return b.gitDirty;
      case Key::build_type: return b.buildType;
      case Key::compiler: return b.compiler;
      case Key::compiler_flags: return b.compilerFlags;
      case Key::simd_targets: return simdTargetsJson();
      case Key::nix: return nixJson();
    }
    unhandledKey("build");
  });
}

nlohmann::json sceneJson(const RunConfig& config, const Scene& scene, double loadMs) {
  using Key = schema::MetadataSceneKey;
  return objectOf<Key>(schema::kMetadataSceneKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::name: return scene.name;
      case Key::path: return config.scenePath.string();
      case Key::sha256: return scene.sha256;
      case Key::spheres: return scene.spheres.size();
      case Key::load_ms: return loadMs;
    }
    unhandledKey("scene");
  });
}

nlohmann::json configJson(const RunConfig& config, const RunIdentity& id) {
  const RendererInfo& r = id.renderer;
  using Key = schema::MetadataConfigKey;
  return objectOf<Key>(schema::kMetadataConfigKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::renderer: return nameOf(r.kind);
      case Key::threads: return r.threads;
      case Key::lanes: return r.lanes;
      case Key::simd_target: return r.simdTarget;
      case Key::grain: return r.grain.value_or(0);  // as in the CSV: 0 and "" without oneTBB
      case Key::partition: return r.partition ? nameOf(*r.partition) : "";
      case Key::algorithm: return nameOf(id.options.algorithm);
      case Key::early_exit: return id.options.earlyExits.toString();
      case Key::accel: return nameOf(id.options.accel);
      // As in the CSV: "" where no traversal applies; the threshold null unless hybrid.
      case Key::traversal: return r.traversal ? nameOf(*r.traversal) : "";
      case Key::hybrid_threshold: return r.hybridThreshold ? nlohmann::json(*r.hybridThreshold) : nullptr;
      // The GPU renderer's axes, as in the CSV: "" where none applies (a CPU renderer; gpu_bvh also accel none).
      case Key::gpu_bvh: return r.gpuBvh ? nameOf(*r.gpuBvh) : "";
      case Key::gpu_schedule: return r.gpuSchedule ? nameOf(*r.gpuSchedule) : "";
      case Key::gpu_path: return r.gpuPath ? nameOf(*r.gpuPath) : "";
      case Key::gpu_rt_reorder: return r.gpuRtReorder ? nameOf(*r.gpuRtReorder) : "";
      case Key::precision: return nameOf(r.precision);
      case Key::agreement: return config.agreement;
      case Key::counters: return id.options.counters;
      case Key::width: return id.extent.width;
      case Key::height: return id.extent.height;
      case Key::warmup_frames: return config.warmupFrames;
      case Key::measured_frames: return config.measuredFrames;
      case Key::present: return nameOf(id.present);
      case Key::present_reason: return id.presentReason;
    }
    unhandledKey("config");
  });
}

nlohmann::json accelStructureJson(const AccelStructureInfo& a) {
  using Key = schema::MetadataAccelStructureKey;
  return objectOf<Key>(schema::kMetadataAccelStructureKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::kind: return nameOf(a.kind);
      case Key::build_ms: return a.buildMs;
      case Key::nodes: return a.nodes ? nlohmann::json(*a.nodes) : nullptr;
      case Key::depth: return a.depth ? nlohmann::json(*a.depth) : nullptr;
      case Key::device_bytes: return a.deviceBytes ? nlohmann::json(*a.deviceBytes) : nullptr;
      case Key::box_padding: return a.padding ? nlohmann::json(nameOf(*a.padding)) : nullptr;
      case Key::estimated_tests_per_ray:
        return a.estimatedTestsPerRay ? nlohmann::json(*a.estimatedTestsPerRay) : nullptr;
      case Key::spheres_kept_apart: return a.spheresKeptApart ? nlohmann::json(*a.spheresKeptApart) : nullptr;
    }
    unhandledKey("accel_structure");
  });
}

nlohmann::json gpuWalkProbeJson(const GpuWalkProbe& probe) {
  using Key = schema::MetadataGpuWalkProbeKey;
  return objectOf<Key>(schema::kMetadataGpuWalkProbeKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::width: return probe.extent.width;
      case Key::height: return probe.extent.height;
      case Key::gpu_ms: {
        nlohmann::json byCandidate = nlohmann::json::object();
        for (const auto& [candidate, ms] : probe.gpuMs) byCandidate[candidate] = ms;
        return byCandidate;
      }
    }
    unhandledKey("gpu_walk_probe");
  });
}

nlohmann::json laneCountersJson(const LaneCounters& c) {
  using Key = schema::MetadataLaneCountersKey;
  return objectOf<Key>(schema::kMetadataLaneCountersKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::rays: return c.rays();
      case Key::rays_per_depth: {
        // Depth 0 (primary rays) first, up to the deepest depth that traced a ray, as the CSV column.
        const auto depths = static_cast<std::size_t>(c.deepestDepth());
        return std::vector<std::uint64_t>(c.raysPerDepth.begin(), c.raysPerDepth.begin() + depths);
      }
      case Key::node_visits: return c.nodeVisits;
      case Key::node_lane_slots: return c.nodeLaneSlots;
      case Key::node_lanes_active: return c.nodeLanesActive;
      case Key::sphere_tests: return c.sphereTests;
      case Key::sphere_lane_slots: return c.sphereLaneSlots;
      case Key::sphere_lanes_active: return c.sphereLanesActive;
      case Key::shade_lane_slots: return c.shadeLaneSlots;
      case Key::shade_lanes_active: return c.shadeLanesActive;
    }
    unhandledKey("lane_counters");
  });
}

nlohmann::json agreementJson(const ImageAgreement& a) {
  using Key = schema::MetadataAgreementKey;
  return objectOf<Key>(schema::kMetadataAgreementKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::reference: return "double";
      case Key::frame: return 0;
      case Key::tolerance: return ImageAgreement::kChannelTolerance;
      case Key::within_tolerance: return a.fractionWithinTolerance;
      // JSON has no infinity: identical images have no PSNR.
      case Key::psnr_db: return std::isfinite(a.psnrDb) ? nlohmann::json(a.psnrDb) : nullptr;
      case Key::max_channel_difference: return a.maxChannelDifference;
    }
    unhandledKey("agreement");
  });
}

nlohmann::json deviceJson(const gpu::DeviceInfo& d, bool validation) {
  using Key = schema::MetadataDeviceKey;
  return objectOf<Key>(schema::kMetadataDeviceKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::index: return d.index;
      case Key::name: return d.name;
      case Key::type: return gpu::nameOf(d.type);
      case Key::vendor_id: return d.vendorId;
      case Key::device_id: return d.deviceId;
      case Key::driver_name: return d.driverName;
      case Key::driver_info: return d.driverInfo;
      case Key::driver_version: return d.driverVersion;
      case Key::driver_version_raw: return d.driverVersionRaw;
      case Key::api_version: return d.apiVersion;
      case Key::timestamp_period_ns: return d.timestampPeriodNs;
      case Key::timestamp_valid_bits: return d.timestampValidBits;
      case Key::validation: return validation;
    }
    unhandledKey("device");
  });
}

nlohmann::json windowJson(const WindowOutcome& window) {
  const gpu::SwapchainInfo& w = window.swapchain;
  using Key = schema::MetadataWindowKey;
  return objectOf<Key>(schema::kMetadataWindowKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::present_mode: return nameOf(w.requested);
      case Key::present_mode_granted: return nameOf(w.granted);
      case Key::surface_format: return w.surfaceFormat;
      case Key::swapchain_images: return w.imageCount;
      case Key::swapchain_recreations: return w.recreations;
      case Key::frames_presented: return w.framesPresented;
      case Key::closed: return window.closed;
    }
    unhandledKey("window");
  });
}

nlohmann::json savedFrameJson(const SaveFrameRequest& request) {
  using Key = schema::MetadataOutputsFramesKey;
  return objectOf<Key>(schema::kMetadataOutputsFramesKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::frame: return request.frame;
      case Key::file: return request.file.string();
    }
    unhandledKey("outputs.frames");
  });
}

nlohmann::json outputsJson(const RunConfig& config) {
  using Key = schema::MetadataOutputsKey;
  return objectOf<Key>(schema::kMetadataOutputsKeyNames, [&](Key key) -> nlohmann::json {
    switch (key) {
      case Key::csv: return config.csvPath ? nlohmann::json(config.csvPath->string()) : nullptr;
      case Key::frames: {
        nlohmann::json frames = nlohmann::json::array();
        for (const auto& s : config.saveFrames) frames.push_back(savedFrameJson(s));
        return frames;
      }
    }
    unhandledKey("outputs");
  });
}

}  // namespace

std::string formatRfc3339(std::chrono::system_clock::time_point t) {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count() % 1000;
  const std::time_t seconds = std::chrono::system_clock::to_time_t(t);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900, utc.tm_mon + 1,
                utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, static_cast<int>(ms));
  return buffer;
}

std::optional<Emulation> emulationOf(std::string_view processName, std::string_view cpuinfo,
                                     std::string_view emulatedCpu) {
  const bool qemu = processName.starts_with("qemu-");
  const std::string_view described = cpuinfoArchitecture(cpuinfo);
  const bool foreignCpu = described != "unknown" && described != kBinaryArchitecture;
  if (!qemu && !foreignCpu) return std::nullopt;
  Emulation e{.emulator = qemu ? std::string(processName) : "unknown",
              .cpu = std::nullopt,
              .hostArchitecture = std::string(described)};
  if (!emulatedCpu.empty()) e.cpu = std::string(emulatedCpu);
  return e;
}

std::string makeRunId(std::chrono::system_clock::time_point startedAt) {
  const std::time_t seconds = std::chrono::system_clock::to_time_t(startedAt);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char stamp[24];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &utc);
  std::random_device entropy;
  char suffix[8];
  std::snprintf(suffix, sizeof suffix, "%06x", entropy() & 0xffffffu);
  return std::string(stamp) + "-" + suffix;
}

nlohmann::json makeRunMetadata(const RunConfig& config, const RunIdentity& identity, const Scene& scene,
                               const RunTimes& times, const std::optional<WindowOutcome>& window,
                               const std::optional<LaneCounters>& laneCounters,
                               const std::optional<ImageAgreement>& agreement) {
  nlohmann::json meta = nlohmann::json::object();
  for (std::size_t i = 0; i < schema::kRunMetadataKeyNames.size(); ++i) {
    const auto key = static_cast<RunMetadataKey>(i);
    nlohmann::json& value = meta[std::string(schema::kRunMetadataKeyNames[i])];
    switch (key) {
      case RunMetadataKey::schema_version: value = schema::kVersion; break;
      case RunMetadataKey::run_id: value = identity.runId; break;
      case RunMetadataKey::command_line: value = config.commandLine; break;
      case RunMetadataKey::scene: value = sceneJson(config, scene, times.loadMs); break;
      case RunMetadataKey::config: value = configJson(config, identity); break;
      case RunMetadataKey::build: value = buildJson(); break;
      case RunMetadataKey::host: value = hostInfo(); break;
      case RunMetadataKey::libraries: value = libraryVersions(); break;
      case RunMetadataKey::started_at: value = formatRfc3339(times.startedAt); break;
      case RunMetadataKey::finished_at: value = formatRfc3339(times.finishedAt); break;
      case RunMetadataKey::outputs: value = outputsJson(config); break;
      case RunMetadataKey::prepare_ms: value = times.prepareMs; break;
      case RunMetadataKey::accel_structure: value = orNull(identity.renderer.accelStructure, accelStructureJson); break;
      case RunMetadataKey::gpu_walk_probe: value = orNull(identity.renderer.gpuWalkProbe, gpuWalkProbeJson); break;
      case RunMetadataKey::lane_counters: value = orNull(laneCounters, laneCountersJson); break;
      case RunMetadataKey::agreement: value = orNull(agreement, agreementJson); break;
      case RunMetadataKey::device:
        value = orNull(identity.device, [&](const gpu::DeviceInfo& d) { return deviceJson(d, identity.validation); });
        break;
      case RunMetadataKey::window: value = orNull(window, windowJson); break;
    }
  }
  return meta;
}

}  // namespace rt
