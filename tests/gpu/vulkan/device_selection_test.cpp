// The Vulkan-free parts of the GPU code: device choice, the device list,
// driver versions, timestamp arithmetic, dispatch sizes, error messages.
#include <gtest/gtest.h>

#include <vector>

#include "gpu/compute/raytrace_pipeline.h"
#include "gpu/vulkan/device_info.h"
#include "gpu/vulkan/timestamps.h"

namespace rt::gpu {
namespace {

DeviceInfo device(std::uint32_t index, std::string name, DeviceType type, std::string unsuitable = "") {
  DeviceInfo d;
  d.index = index;
  d.name = std::move(name);
  d.type = type;
  d.driverName = "driver";
  d.driverVersion = "1.0.0";
  d.apiVersion = "1.3.0";
  d.unsuitableReason = std::move(unsuitable);
  return d;
}

const std::vector<DeviceInfo> kMachine{device(0, "llvmpipe (LLVM 15.0.6, 256 bits)", DeviceType::cpu),
                                       device(1, "Intel(R) UHD Graphics 770", DeviceType::integrated),
                                       device(2, "NVIDIA H100 80GB HBM3", DeviceType::discrete)};

TEST(ChooseDevice, DefaultPrefersDiscreteThenIntegratedThenCpu) {
  EXPECT_EQ(chooseDevice(kMachine, ""), 2u);
  EXPECT_EQ(chooseDevice(std::span(kMachine).first(2), ""), 1u);
  EXPECT_EQ(chooseDevice(std::span(kMachine).first(1), ""), 0u);
}

TEST(ChooseDevice, DefaultSkipsUnsuitableDevices) {
  std::vector<DeviceInfo> devices = kMachine;
  devices[2].unsuitableReason = "Vulkan 1.1.0 < 1.2";
  EXPECT_EQ(chooseDevice(devices, ""), 1u);
}

TEST(ChooseDevice, ByIndex) {
  EXPECT_EQ(chooseDevice(kMachine, "0"), 0u);
  EXPECT_EQ(chooseDevice(kMachine, "1"), 1u);
}

TEST(ChooseDevice, ByCaseInsensitiveNameSubstring) {
  EXPECT_EQ(chooseDevice(kMachine, "LLVMpipe"), 0u);
  EXPECT_EQ(chooseDevice(kMachine, "h100"), 2u);
}

TEST(ChooseDevice, FailuresListWhatWasFound) {
  for (const char* selector : {"7", "radeon", "1x"}) {
    try {
      (void)chooseDevice(kMachine, selector);
      FAIL() << "selector " << selector << " chose a device";
    } catch (const DeviceUnavailable& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(selector), std::string::npos) << message;
      EXPECT_NE(message.find("NVIDIA H100 80GB HBM3"), std::string::npos) << message;
      EXPECT_NE(message.find("llvmpipe"), std::string::npos) << message;
    }
  }
}

TEST(ChooseDevice, NoDeviceAtAll) {
  try {
    (void)chooseDevice({}, "");
    FAIL() << "chose a device from none";
  } catch (const DeviceUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("(none)"), std::string::npos) << e.what();
  }
}

TEST(ChooseDevice, AnUnsuitableDeviceNamedExplicitlyIsRefusedWithTheReason) {
  std::vector<DeviceInfo> devices = kMachine;
  devices[0].unsuitableReason = "no compute queue";
  EXPECT_THROW((void)chooseDevice(devices, "0"), DeviceUnavailable);
  try {
    (void)chooseDevice(devices, "llvm");
  } catch (const DeviceUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("no compute queue"), std::string::npos) << e.what();
  }
}

TEST(FormatDeviceList, OneLinePerDeviceWithTheChoiceMarked) {
  const std::string text = formatDeviceList(kMachine, 2);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);
  EXPECT_NE(text.find("  2*  NVIDIA H100 80GB HBM3  type=discrete  driver=driver 1.0.0  api=1.3.0"), std::string::npos)
      << text;
  EXPECT_NE(text.find("  0   llvmpipe"), std::string::npos) << text;
}

TEST(DecodeDriverVersion, NvidiaPacksTenEightEightSixBits) {
  // 580.159.4 as NVIDIA encodes it.
  const std::uint32_t v = (580u << 22) | (159u << 14) | (4u << 6);
  EXPECT_EQ(decodeDriverVersion(0x10DE, v), "580.159.4");
}

TEST(DecodeDriverVersion, OthersUseTheVulkanVersionEncoding) {
  EXPECT_EQ(decodeDriverVersion(0x10005, (22u << 22) | (3u << 12) | 6u), "22.3.6");
  EXPECT_EQ(decodeDriverVersion(0x10005, 1u), "0.0.1");
}

TEST(TimestampDelta, AppliesThePeriod) {
  EXPECT_DOUBLE_EQ(timestampDeltaMs(1000, 3'001'000, 64, 1.0), 3.0);
  EXPECT_DOUBLE_EQ(timestampDeltaMs(0, 1'000'000, 64, 0.5), 0.5);
}

TEST(TimestampDelta, HonoursValidBitsAcrossAWrap) {
  // A 36-bit counter that wrapped between the two timestamps.
  const std::uint64_t max36 = (std::uint64_t{1} << 36) - 1;
  EXPECT_DOUBLE_EQ(timestampDeltaMs(max36 - 499'999, 500'000, 36, 1.0), 1.0);
  // Bits above validBits are garbage and ignored.
  const std::uint64_t junk = std::uint64_t{0xABC} << 40;
  EXPECT_DOUBLE_EQ(timestampDeltaMs(junk | 10, (junk << 1) | 2'000'010, 36, 1.0), 2.0);
}

TEST(WorkgroupCount, RoundsUp) {
  EXPECT_EQ(workgroupCount(96, 8), 12u);
  EXPECT_EQ(workgroupCount(101, 8), 13u);
  EXPECT_EQ(workgroupCount(1, 8), 1u);
  EXPECT_EQ(workgroupCount(37, 8), 5u);
}

TEST(DescribeVulkanFailure, NamesTheWorkTheResultAndTheLikelyCause) {
  const std::string lost = describeVulkanFailure("render", vk::Result::eErrorDeviceLost, "vk::Queue::submit");
  EXPECT_NE(lost.find("render"), std::string::npos) << lost;
  EXPECT_NE(lost.find("ErrorDeviceLost"), std::string::npos) << lost;
  EXPECT_NE(lost.find("device was lost"), std::string::npos) << lost;
  const std::string oom = describeVulkanFailure("prepare", vk::Result::eErrorOutOfDeviceMemory, "");
  EXPECT_NE(oom.find("out of device memory"), std::string::npos) << oom;
}

}  // namespace
}  // namespace rt::gpu
