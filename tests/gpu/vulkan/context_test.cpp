// Opening the Vulkan device, and the checks every other GPU test relies
// on: the validation layer is live and its messages are counted.
#include <gtest/gtest.h>

#include "gpu/gpu_test_support.h"
#include "gpu/vulkan/device.h"

namespace rt::test {
namespace {

using ContextTest = ValidatedGpuTest;

TEST_F(ContextTest, DescribesTheDeviceForTheMetadata) {
  const gpu::DeviceInfo& info = context()->info();
  EXPECT_FALSE(info.name.empty());
  EXPECT_FALSE(info.driverName.empty());
  EXPECT_FALSE(info.driverVersion.empty());
  EXPECT_TRUE(info.suitable()) << info.unsuitableReason;
  EXPECT_GT(info.timestampPeriodNs, 0.0);
  EXPECT_EQ(info.apiVersion.rfind("1.", 0), 0u);
  EXPECT_TRUE(context()->validationEnabled());
}

TEST_F(ContextTest, ListsTheDeviceItOpened) {
  const std::vector<gpu::DeviceInfo> devices = gpu::listDevices({});
  ASSERT_FALSE(devices.empty());
  ASSERT_LT(context()->info().index, devices.size());
  EXPECT_EQ(devices[context()->info().index].name, context()->info().name);
}

TEST_F(ContextTest, SelectsByIndexAndByName) {
  const gpu::DeviceInfo& info = context()->info();
  EXPECT_EQ(gpu::Context::open({.deviceSelector = std::to_string(info.index)})->info().name, info.name);
  EXPECT_EQ(gpu::Context::open({.deviceSelector = info.name.substr(0, 4)})->info().index,
            gpu::chooseDevice(gpu::listDevices({}), info.name.substr(0, 4)));
}

TEST_F(ContextTest, UnknownDeviceNameIsAClearError) {
  try {
    (void)gpu::Context::open({.deviceSelector = "no-such-gpu-anywhere"});
    FAIL() << "opened a device that does not exist";
  } catch (const gpu::DeviceUnavailable& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("no-such-gpu-anywhere"), std::string::npos) << message;
    EXPECT_NE(message.find(context()->info().name), std::string::npos) << "lists what was found: " << message;
  }
}

TEST(ContextWithoutLoader, IsAClearError) {
  try {
    (void)gpu::Context::open({.loaderLibrary = "libvulkan-that-does-not-exist.so.1"});
    FAIL() << "opened a device without a loader";
  } catch (const gpu::DeviceUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("no Vulkan loader"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("libvulkan-that-does-not-exist.so.1"), std::string::npos) << e.what();
  }
}

// The layer is really loaded and its messages really counted: an invalid
// call is reported. On a context of its own, so the shared one stays clean.
TEST(ValidationLayer, CountsAnInvalidCall) {
  const auto context = gpu::Context::open({.validation = true});
  ASSERT_EQ(context->validationMessages().total(), 0u);
  // VkFenceCreateInfo::flags has one valid bit (SIGNALED = 1); drivers ignore the others.
  const auto invalidFlags = static_cast<vk::FenceCreateFlagBits>(0x4);
  const vk::raii::Fence fence(context->device().logical(), vk::FenceCreateInfo{.flags = invalidFlags});
  EXPECT_GE(context->validationMessages().errors, 1u);
}

TEST(ValidationLayer, IsOffUnlessAskedFor) {
  const auto context = gpu::Context::open({});
  EXPECT_FALSE(context->validationEnabled());
  EXPECT_EQ(context->validationCounter(), nullptr);
}

}  // namespace
}  // namespace rt::test
