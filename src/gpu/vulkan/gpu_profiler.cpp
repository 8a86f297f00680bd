#include "gpu/vulkan/gpu_profiler.h"

namespace rt::gpu {

#ifdef TRACY_ENABLE

GpuProfiler::GpuProfiler(const Device& device, CommandRunner& runner) : runner_(runner) {
  const auto getInstanceProcAddr = device.instance().getInstanceProcAddr();
  const auto instance = static_cast<VkInstance>(*device.instance().get());
  const auto getDeviceProcAddr =
      reinterpret_cast<PFN_vkGetDeviceProcAddr>(getInstanceProcAddr(instance, "vkGetDeviceProcAddr"));
  // Tracy records its calibration into the runner's idle command buffer and
  // submits it itself, waiting for the queue.
  context_ =
      TracyVkContext(instance, static_cast<VkPhysicalDevice>(*device.physical()),
                     static_cast<VkDevice>(*device.logical()), static_cast<VkQueue>(*device.queue()),
                     static_cast<VkCommandBuffer>(*runner.idleCommandBuffer()), getInstanceProcAddr, getDeviceProcAddr);
  static constexpr char kName[] = "Vulkan queue";
  TracyVkContextName(context_, kName, sizeof kName - 1);
}

GpuProfiler::~GpuProfiler() {
  // Frames collect the zones of the frame before; the last frame's are
  // collected here, or the capture would miss them.
  try {
    runner_.run("Tracy GPU collect", [&](const vk::raii::CommandBuffer& cb) { TracyVkCollect(context_, *cb); });
  } catch (const std::exception&) {
    // A lost device loses the last zones too; destruction goes on.
  }
  TracyVkDestroy(context_);
}

#else

GpuProfiler::GpuProfiler(const Device&, CommandRunner&) {}
GpuProfiler::~GpuProfiler() = default;

#endif

}  // namespace rt::gpu
