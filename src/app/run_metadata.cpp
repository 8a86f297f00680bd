#include "app/run_metadata.h"

#include <sys/utsname.h>

#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "app/build_info.h"
#include "core/sha256.h"

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
  return {{"cpu_model", cpu},
          {"logical_cores", std::thread::hardware_concurrency()},
          {"os", os},
          {"kernel", kernel}};
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
  return {{"nixpkgs_rev", rev != nullptr && *rev != '\0' ? rev : "unknown"}};
}

nlohmann::json buildJson() {
  const BuildInfo& b = buildInfo();
  return {{"version", b.version},         {"git_commit", b.gitCommit}, {"git_dirty", b.gitDirty},
          {"build_type", b.buildType},    {"compiler", b.compiler},    {"compiler_flags", b.compilerFlags},
          {"nix", nixJson()}};
}

nlohmann::json configJson(const RunConfig& config, const RunIdentity& id) {
  return {{"renderer", nameOf(id.renderer.kind)},
          {"threads", id.renderer.threads},
          {"lanes", id.renderer.lanes},
          {"simd_target", id.renderer.simdTarget},
          {"grain", id.renderer.grain.value_or(0)},  // as in the CSV: 0 and "" without oneTBB
          {"partition", id.renderer.partition ? nameOf(*id.renderer.partition) : ""},
          {"algorithm", nameOf(id.options.algorithm)},
          {"early_exit", id.options.earlyExits.toString()},
          {"accel", nameOf(id.options.accel)},
          {"width", id.extent.width},
          {"height", id.extent.height},
          {"warmup_frames", config.warmupFrames},
          {"measured_frames", config.measuredFrames},
          {"present", nameOf(id.present)},
          {"present_reason", id.presentReason}};
}

nlohmann::json accelStructureJson(const RendererInfo& renderer) {
  if (!renderer.accelStructure) return nullptr;
  const AccelStructureInfo& a = *renderer.accelStructure;
  return {{"kind", nameOf(a.kind)}, {"build_ms", a.buildMs}, {"nodes", a.nodes}, {"depth", a.depth}};
}

nlohmann::json deviceJson(const RunIdentity& id) {
  if (!id.device) return nullptr;
  const gpu::DeviceInfo& d = *id.device;
  return {{"index", d.index},
          {"name", d.name},
          {"type", gpu::nameOf(d.type)},
          {"vendor_id", d.vendorId},
          {"device_id", d.deviceId},
          {"driver_name", d.driverName},
          {"driver_info", d.driverInfo},
          {"driver_version", d.driverVersion},
          {"driver_version_raw", d.driverVersionRaw},
          {"api_version", d.apiVersion},
          {"timestamp_period_ns", d.timestampPeriodNs},
          {"timestamp_valid_bits", d.timestampValidBits},
          {"validation", id.validation}};
}

nlohmann::json windowJson(const RunIdentity& id) {
  if (!id.swapchain) return nullptr;
  const gpu::SwapchainInfo& w = *id.swapchain;
  return {{"present_mode", nameOf(w.requested)},
          {"present_mode_granted", nameOf(w.granted)},
          {"surface_format", w.surfaceFormat},
          {"swapchain_images", w.imageCount},
          {"swapchain_recreations", w.recreations},
          {"frames_presented", w.framesPresented},
          {"closed", id.windowClosed}};
}

nlohmann::json outputsJson(const RunConfig& config) {
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& s : config.saveFrames) frames.push_back({{"frame", s.frame}, {"file", s.file.string()}});
  return {{"csv", config.csvPath ? nlohmann::json(config.csvPath->string()) : nlohmann::json(nullptr)},
          {"frames", frames}};
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
                               const RunTimes& times) {
  nlohmann::json meta = nlohmann::json::object();
  for (std::size_t i = 0; i < schema::kRunMetadataKeyNames.size(); ++i) {
    const auto key = static_cast<RunMetadataKey>(i);
    nlohmann::json& value = meta[std::string(schema::kRunMetadataKeyNames[i])];
    switch (key) {
      case RunMetadataKey::schema_version: value = schema::kVersion; break;
      case RunMetadataKey::run_id: value = identity.runId; break;
      case RunMetadataKey::command_line: value = config.commandLine; break;
      case RunMetadataKey::scene:
        value = {{"name", scene.name},
                 {"path", config.scenePath.string()},
                 {"sha256", scene.sha256},
                 {"spheres", scene.spheres.size()}};
        break;
      case RunMetadataKey::config: value = configJson(config, identity); break;
      case RunMetadataKey::build: value = buildJson(); break;
      case RunMetadataKey::host: value = hostInfo(); break;
      case RunMetadataKey::libraries: value = libraryVersions(); break;
      case RunMetadataKey::started_at: value = formatRfc3339(times.startedAt); break;
      case RunMetadataKey::finished_at: value = formatRfc3339(times.finishedAt); break;
      case RunMetadataKey::outputs: value = outputsJson(config); break;
      case RunMetadataKey::accel_structure: value = accelStructureJson(identity.renderer); break;
      case RunMetadataKey::device: value = deviceJson(identity); break;
      case RunMetadataKey::window: value = windowJson(identity); break;
    }
  }
  return meta;
}

}  // namespace rt
