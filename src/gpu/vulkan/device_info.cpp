#include "gpu/vulkan/device_info.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <sstream>

namespace rt::gpu {
namespace {

constexpr std::uint32_t kVendorNvidia = 0x10DE;

std::string lowercase(std::string_view text) {
  std::string out(text);
  std::ranges::transform(out, out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

std::optional<std::size_t> parseIndex(std::string_view selector) {
  std::size_t index = 0;
  const auto [end, ec] = std::from_chars(selector.data(), selector.data() + selector.size(), index);
  if (ec != std::errc() || end != selector.data() + selector.size()) return std::nullopt;
  return index;
}

// Lower is preferred by the default choice.
int preferenceRank(DeviceType type) {
  switch (type) {
    case DeviceType::discrete: return 0;
    case DeviceType::integrated: return 1;
    case DeviceType::virtual_gpu: return 2;
    case DeviceType::cpu: return 3;
    case DeviceType::other: return 4;
  }
  return 5;
}

[[noreturn]] void throwUnavailable(std::span<const DeviceInfo> devices, const std::string& problem) {
  throw DeviceUnavailable(problem + "\nVulkan devices found:\n" +
                          (devices.empty() ? std::string("  (none)\n") : formatDeviceList(devices, std::nullopt)));
}

std::size_t requireSuitable(std::span<const DeviceInfo> devices, std::size_t index, std::string_view selector) {
  const DeviceInfo& d = devices[index];
  if (!d.suitable()) {
    throwUnavailable(devices, "--device " + std::string(selector) + " selects '" + d.name +
                                  "', which cannot run the renderer: " + d.unsuitableReason);
  }
  return index;
}

}  // namespace

std::string_view nameOf(DeviceType type) {
  switch (type) {
    case DeviceType::discrete: return "discrete";
    case DeviceType::integrated: return "integrated";
    case DeviceType::virtual_gpu: return "virtual";
    case DeviceType::cpu: return "cpu";
    case DeviceType::other: return "other";
  }
  return "other";
}

std::size_t chooseDevice(std::span<const DeviceInfo> devices, std::string_view selector) {
  if (devices.empty()) throwUnavailable(devices, "no Vulkan device found");
  if (selector.empty()) {
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < devices.size(); ++i) {
      if (!devices[i].suitable()) continue;
      if (!best || preferenceRank(devices[i].type) < preferenceRank(devices[*best].type)) best = i;
    }
    if (!best) throwUnavailable(devices, "no Vulkan device can run the renderer");
    return *best;
  }
  if (const auto index = parseIndex(selector)) {
    if (*index >= devices.size()) {
      throwUnavailable(devices, "--device " + std::string(selector) + ": there is no device with that index");
    }
    return requireSuitable(devices, *index, selector);
  }
  const std::string wanted = lowercase(selector);
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (lowercase(devices[i].name).find(wanted) != std::string::npos) return requireSuitable(devices, i, selector);
  }
  throwUnavailable(devices, "--device " + std::string(selector) + ": no device name contains it");
}

std::string formatDeviceList(std::span<const DeviceInfo> devices, std::optional<std::size_t> chosen) {
  std::ostringstream out;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const DeviceInfo& d = devices[i];
    out << "  " << d.index << (chosen == i ? "*" : " ") << "  " << d.name << "  type=" << nameOf(d.type)
        << "  driver=" << d.driverName << " " << d.driverVersion;
    if (!d.driverInfo.empty()) out << " (" << d.driverInfo << ")";
    out << "  api=" << d.apiVersion;
    if (!d.suitable()) out << "  unsuitable: " << d.unsuitableReason;
    out << "\n";
  }
  return out.str();
}

std::string decodeDriverVersion(std::uint32_t vendorId, std::uint32_t v) {
  std::array<std::uint32_t, 3> parts{};
  if (vendorId == kVendorNvidia) {
    parts = {(v >> 22) & 0x3ffu, (v >> 14) & 0xffu, (v >> 6) & 0xffu};
  } else {
    parts = {(v >> 22) & 0x7fu, (v >> 12) & 0x3ffu, v & 0xfffu};  // VK_API_VERSION_MAJOR/MINOR/PATCH
  }
  return std::to_string(parts[0]) + "." + std::to_string(parts[1]) + "." + std::to_string(parts[2]);
}

}  // namespace rt::gpu
