#include "gpu/present/device_renderer.h"

#include <stdexcept>
#include <utility>

#include "gpu/present/shader_output.h"
#include "gpu/present/swapchain.h"
#include "gpu/vulkan/context.h"
#include "gpu/vulkan/frame_commands.h"

namespace rt::gpu {

DeviceRenderer::DeviceRenderer(std::string name, std::shared_ptr<Context> context, PresentMode present,
                               std::shared_ptr<Swapchain> window)
    : name_(std::move(name)), context_(std::move(context)), presentMode_(present), window_(std::move(window)) {
  if (!context_) throw std::invalid_argument("the " + name_ + " needs a Vulkan device");
  if (presentMode_ == PresentMode::window && !window_)
    throw std::invalid_argument("present mode 'window' needs a swapchain");
  frames_ = translateVulkanErrors(name_ + " set-up", [&] { return std::make_unique<FrameCommands>(device()); });
}

DeviceRenderer::~DeviceRenderer() = default;

void DeviceRenderer::present() { output().present(frames_->runner(), frames_->profiler(), window_.get()); }

void DeviceRenderer::readPresented(Image& target) { output().readPresented(frames_->runner(), target); }

const Device& DeviceRenderer::device() const { return context_->device(); }

RendererInfo DeviceRenderer::deviceInfo(RendererKind kind) {
  RendererInfo info;
  info.kind = kind;
  info.threads = 0;  // the device schedules the work
  info.lanes = 0;
  return info;
}

void DeviceRenderer::beginPrepare(const Scene& scene) {
  if (scene.spheres.empty()) throw std::invalid_argument("the " + name_ + " needs at least one sphere");
  if (window_) translateVulkanErrors(name_ + " prepare", [&] { device().logical().waitIdle(); });
  gpuMs_.reset();
}

void DeviceRenderer::waitForWindowAtEnd() noexcept {
  if (!window_) return;  // every other phase waited for its own work
  try {
    device().logical().waitIdle();
  } catch (const vk::SystemError&) {
    // A lost device runs nothing that could still read the images.
  }
}

}  // namespace rt::gpu
