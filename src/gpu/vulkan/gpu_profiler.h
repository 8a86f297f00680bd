#pragma once
// Tracy's GPU timeline for the device's queue. With RT_TRACY=OFF the
// TracyVk macros used here expand to nothing and the profiler holds nothing.
#include "gpu/vulkan/device.h"
#include "gpu/vulkan/resources.h"

#ifdef TRACY_ENABLE
// The loader is opened at run time (gpu::LoaderLibrary), so Tracy must reach
// Vulkan through function pointers rather than linked symbols.
#define TRACY_VK_USE_SYMBOL_TABLE
#include <tracy/TracyVulkan.hpp>
#else
#define TracyVkZone(ctx, cmdbuf, name)
#define TracyVkZoneTransient(ctx, varname, cmdbuf, name, active)
#define TracyVkCollect(ctx, cmdbuf)
#endif

namespace rt::gpu {

// Declare it after the CommandRunner it is given: its destructor uses the
// runner to collect the last frame's zones.
class GpuProfiler {
 public:
  GpuProfiler(const Device& device, CommandRunner& runner);
  ~GpuProfiler();
  GpuProfiler(const GpuProfiler&) = delete;
  GpuProfiler& operator=(const GpuProfiler&) = delete;

#ifdef TRACY_ENABLE
  // The plain TracyVkContext: the calibrated variants misbehave on lavapipe
  // (one falls back to the device time domain, the other aborts).
  [[nodiscard]] tracy::VkCtx* context() const { return context_; }

 private:
  CommandRunner& runner_;
  tracy::VkCtx* context_ = nullptr;
#endif
};

}  // namespace rt::gpu
