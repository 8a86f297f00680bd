#pragma once
// --window: the window, the Vulkan device opened for it and the swapchain
// on its surface, and the frame loop's view of them. Built with RT_WINDOW
// only (window_session.cpp); this header has neither GLFW nor Vulkan.
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "app/frame_loop.h"
#include "app/run_config.h"
#include "gpu/present/window_presentation.h"
#include "gpu/vulkan/context.h"

namespace rt {

namespace window {
class GlfwWindow;
}

class WindowSession final : public LiveView {
 public:
  // Opens a window of the render size, then a device whose instance has the
  // window's surface extensions (`options` otherwise), then the swapchain.
  // Throws gpu::WindowUnavailable or gpu::DeviceUnavailable (exit 3).
  static std::shared_ptr<WindowSession> open(const RunConfig& config, gpu::ContextOptions options);
  ~WindowSession() override;  // restores the SIGINT and SIGTERM handlers
  WindowSession(const WindowSession&) = delete;
  WindowSession& operator=(const WindowSession&) = delete;

  [[nodiscard]] const std::shared_ptr<gpu::Context>& context() const { return context_; }
  [[nodiscard]] const std::shared_ptr<gpu::Swapchain>& swapchain() const { return swapchain_; }
  [[nodiscard]] gpu::SwapchainInfo swapchainInfo() const;
  // The window was closed (not run to the last frame).
  [[nodiscard]] bool closed() const { return closed_; }

  bool keepRunning() override;
  [[nodiscard]] std::optional<double> lastAcquireMs() const override;
  void frameDone(const FrameRecord& record) override;

  struct Key {};  // only open() makes sessions
  WindowSession(Key, std::string title, std::shared_ptr<window::GlfwWindow> window);

 private:
  std::string title_;  // renderer and scene; the frame time is appended
  std::shared_ptr<window::GlfwWindow> window_;
  std::shared_ptr<gpu::Context> context_;
  std::shared_ptr<gpu::Swapchain> swapchain_;
  std::chrono::steady_clock::time_point titleShown_{};
  bool closed_ = false;
};

}  // namespace rt
