#pragma once
// A window's presentation as the app and the window see it, without
// Vulkan-Hpp (only the C handle types): the window side a swapchain is
// built on (SurfaceHost), what it reports (SwapchainInfo), and how it is made.
#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <memory>
#include <string>

#include "core/image.h"
#include "gpu/vulkan/device_info.h"
#include "render/render_options.h"

namespace rt::gpu {

using schema::SwapchainPresentMode;

// --window where no window can be opened (no display, no GLFW Vulkan
// support): like a missing device, exit code 3.
class WindowUnavailable : public DeviceUnavailable {
 public:
  using DeviceUnavailable::DeviceUnavailable;
};

// The window a surface belongs to, as the swapchain needs it: its size,
// and whether it changed. Implemented by the GLFW window (src/window).
class SurfaceHost {
 public:
  virtual ~SurfaceHost() = default;
  // The drawable size in pixels now; zero while the window is minimised.
  [[nodiscard]] virtual Extent framebufferSize() const = 0;
  // Blocks (handling events) while the window has no drawable area.
  // Returns false when the window was closed meanwhile.
  virtual bool waitWhileMinimised() = 0;
  // True once after each change of the window's size.
  virtual bool takeResized() = 0;
};

// The run's metadata "window" object (schema run_metadata).
struct SwapchainInfo {
  SwapchainPresentMode requested = SwapchainPresentMode::fifo;
  SwapchainPresentMode granted = SwapchainPresentMode::fifo;  // requested, or fifo where the surface lacks it
  std::string surfaceFormat;
  std::uint32_t imageCount = 0;
  std::uint32_t recreations = 0;  // after the first: resizes, out-of-date or suboptimal swapchains
  std::uint64_t framesPresented = 0;
};

class Context;
class Swapchain;

// The context's VkInstance, on which a window makes its surface.
VkInstance instanceHandle(const Context& context);

// A swapchain on `surface`, a surface the window made on the context's
// instance; it is owned (and destroyed) by the swapchain from here on, also
// when this throws (DeviceUnavailable: the device cannot present to it).
std::shared_ptr<Swapchain> makeSwapchain(std::shared_ptr<Context> context, std::shared_ptr<SurfaceHost> host,
                                         VkSurfaceKHR surface, SwapchainPresentMode requested);

}  // namespace rt::gpu
