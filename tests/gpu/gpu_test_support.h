#pragma once
// Shared by the GPU tests: one Vulkan context per test process with the
// validation layer on, and a fixture that fails a test on any validation
// warning or error it caused (the layer prints them to stderr).
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

#include "gpu/vulkan/context.h"
#include "render/render_test_support.h"

namespace rt::test {

// Holds the context, so that its destruction, where Vulkan reports objects
// left alive, is checked too: after the last test of the process.
class ValidatedGpuEnvironment : public ::testing::Environment {
 public:
  static std::shared_ptr<gpu::Context> context() {
    if (!instance_->context_) {
      // RT_TEST_DEVICE: a --device selector, for machines with several devices.
      const char* selector = std::getenv("RT_TEST_DEVICE");
      instance_->context_ = gpu::Context::open({.deviceSelector = selector ? selector : "", .validation = true});
    }
    return instance_->context_;
  }

  void TearDown() override {
    if (!context_) return;
    const auto counter = context_->validationCounter();
    const gpu::ValidationCounts before = counter->counts();
    context_.reset();  // the last owner: device and instance are destroyed here
    const gpu::ValidationCounts after = counter->counts();
    EXPECT_EQ(after.total(), before.total()) << "validation messages while destroying the device (printed above)";
  }

 private:
  friend ValidatedGpuEnvironment* registerEnvironment();
  static inline ValidatedGpuEnvironment* instance_ = nullptr;
  std::shared_ptr<gpu::Context> context_;
};

// gtest owns registered environments; this registers ours once per process.
inline ValidatedGpuEnvironment* registerEnvironment() {
  static ValidatedGpuEnvironment* const environment = [] {
    auto owned = std::make_unique<ValidatedGpuEnvironment>();
    ValidatedGpuEnvironment::instance_ = owned.get();
    ::testing::AddGlobalTestEnvironment(owned.release());
    return ValidatedGpuEnvironment::instance_;
  }();
  return environment;
}

// Base of every test that touches the device.
class ValidatedGpuTest : public ::testing::Test {
 protected:
  static std::shared_ptr<gpu::Context> context() { return ValidatedGpuEnvironment::context(); }

  void SetUp() override { before_ = context()->validationMessages(); }
  void TearDown() override {
    const gpu::ValidationCounts after = context()->validationMessages();
    EXPECT_EQ(after.errors, before_.errors) << "Vulkan validation errors (printed above)";
    EXPECT_EQ(after.warnings, before_.warnings) << "Vulkan validation warnings (printed above)";
  }

 private:
  static inline ValidatedGpuEnvironment* const registered_ = registerEnvironment();
  gpu::ValidationCounts before_;
};

// Base of the tests that need a second context, opened with options the
// shared one lacks (ray tracing, shaderFloat16), with validation, whose
// messages fail a test as the shared context's do. `Needs` says how:
// options() for the second context, offeredBy(shared context) whether the
// device has what it needs (asked of Vulkan, not of the code under test),
// and kWithout, why a test is skipped where it has not.
template <class Needs>
class SecondContextGpuTest : public ValidatedGpuTest {
 protected:
  static std::shared_ptr<gpu::Context> secondContext() {
    static const std::shared_ptr<gpu::Context> opened = gpu::Context::open(Needs::options());
    return opened;
  }
  void SetUp() override {
    ValidatedGpuTest::SetUp();
    if (!Needs::offeredBy(*context())) GTEST_SKIP() << Needs::kWithout;
    secondBefore_ = secondContext()->validationMessages();
  }
  void TearDown() override {
    ValidatedGpuTest::TearDown();
    if (IsSkipped()) return;
    EXPECT_EQ(secondContext()->validationMessages().total(), secondBefore_.total())
        << "Vulkan validation messages (printed above)";
  }

 private:
  gpu::ValidationCounts secondBefore_;
};

}  // namespace rt::test
