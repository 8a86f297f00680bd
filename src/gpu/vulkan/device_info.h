#pragma once
// What the application knows about Vulkan devices, without Vulkan headers:
// the description recorded in the run metadata and printed by
// --list-devices, the --device choice, and the errors the binary maps to
// exit codes.
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rt::gpu {

// The Vulkan API version this program is written against: the minimum a
// device must offer (driver properties are core in 1.2).
inline constexpr std::uint32_t kRequiredApiMajor = 1;
inline constexpr std::uint32_t kRequiredApiMinor = 2;

enum class DeviceType { discrete, integrated, virtual_gpu, cpu, other };
std::string_view nameOf(DeviceType type);

struct DeviceInfo {
  std::uint32_t index = 0;  // position in the loader's enumeration: what --device INDEX counts
  std::string name{};
  DeviceType type = DeviceType::other;
  std::uint32_t vendorId = 0;
  std::uint32_t deviceId = 0;
  std::string driverName{};     // VkPhysicalDeviceDriverProperties::driverName ("llvmpipe", "NVIDIA")
  std::string driverInfo{};     // e.g. "Mesa 22.3.6 (LLVM 15.0.6)", "580.159.04"
  std::string driverVersion{};  // driverVersion decoded by the vendor's convention
  std::uint32_t driverVersionRaw = 0;
  std::string apiVersion{};              // "1.3.230"
  double timestampPeriodNs = 0.0;        // nanoseconds per timestamp tick
  std::uint32_t timestampValidBits = 0;  // of the queue family used; 0: no timestamps
  std::string unsuitableReason{};        // empty when the renderer can run on it

  [[nodiscard]] bool suitable() const { return unsuitableReason.empty(); }
};

// No Vulkan loader, no device, or no device matching --device: the run
// cannot do what it was asked to (exit code 3). The message lists what was found.
class DeviceUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The device lacks an optional feature that the run's options need (--precision
// f16: shaderFloat16): those options cannot run on it (exit code 2, as for an
// option a renderer refuses). The message names the device and the feature.
class FeatureUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A Vulkan call failed while the device was in use (device lost, out of
// memory, a fence that never signals): the message says what was being
// done and the VkResult.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The device a run uses, by index into `devices`. `selector` is --device:
// an index ("0") or a case-insensitive substring of the name ("llvmpipe",
// "h100"); empty picks the first discrete GPU, else integrated, else
// virtual, else CPU (lavapipe). Only suitable devices are chosen; throws
// DeviceUnavailable listing the devices otherwise.
std::size_t chooseDevice(std::span<const DeviceInfo> devices, std::string_view selector);

// --list-devices: one line per device; `chosen` is marked as the default.
std::string formatDeviceList(std::span<const DeviceInfo> devices, std::optional<std::size_t> chosen);

// driverVersion as the vendor encodes it (NVIDIA: 10.8.8.6 bits; others: VK_MAKE_API_VERSION).
std::string decodeDriverVersion(std::uint32_t vendorId, std::uint32_t driverVersion);

}  // namespace rt::gpu
