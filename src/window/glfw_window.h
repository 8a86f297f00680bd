#pragma once
// The window of a --window run (GLFW, no client API: Vulkan presents into
// it). Only the C Vulkan types appear here; the swapchain is in src/gpu/present.
#include <vulkan/vulkan_core.h>

#include <memory>
#include <string>
#include <vector>

#include "gpu/present/window_presentation.h"

namespace rt::window {

class GlfwWindow final : public gpu::SurfaceHost {
 public:
  // Opens a resizable window of `size` pixels. `loaderLibrary` is the
  // Vulkan loader the run opens (gpu::ContextOptions); GLFW 3.4 and later
  // are handed it, so the surface is made through the same loader (GLFW 3.3
  // opens libvulkan.so.1 itself). Throws gpu::WindowUnavailable when there
  // is no display or GLFW has no Vulkan support. One window per process.
  GlfwWindow(Extent size, const std::string& title, const std::string& loaderLibrary);
  ~GlfwWindow() override;
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  // The instance extensions a surface of this window needs (VK_KHR_surface and the platform's).
  [[nodiscard]] std::vector<std::string> requiredInstanceExtensions() const;
  // A surface on `instance`; the caller owns and destroys it before the window.
  [[nodiscard]] VkSurfaceKHR createSurface(VkInstance instance) const;

  // Handles pending events; false once the window was asked to close
  // (close button, Esc, requestClose()).
  bool pollOpen();
  void requestClose();
  void setTitle(const char* title);

  [[nodiscard]] Extent framebufferSize() const override;
  bool waitWhileMinimised() override;
  bool takeResized() override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace rt::window
