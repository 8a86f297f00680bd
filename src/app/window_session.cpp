#include "app/window_session.h"

#include <array>
#include <atomic>
#include <csignal>
#include <cstdio>

#include "gpu/present/swapchain.h"
#include "window/glfw_window.h"

namespace rt {
namespace {

// SIGINT/SIGTERM close the window like its close button: the frames so far
// are written. A handler may only set a lock-free flag.
std::atomic<bool> closeSignalled{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void requestCloseOnSignal(int /*signal*/) { closeSignalled.store(true, std::memory_order_relaxed); }

using SignalHandler = void (*)(int);
SignalHandler previousInt = SIG_DFL;
SignalHandler previousTerm = SIG_DFL;

// The title's frame time is refreshed this often: often enough to read, not
// so often that the window system is busy with it.
constexpr auto kTitleInterval = std::chrono::milliseconds(250);

}  // namespace

std::shared_ptr<WindowSession> WindowSession::open(const RunConfig& config, gpu::ContextOptions options) {
  std::string title = "raytracer - " + std::string(nameOf(config.renderer)) + " - " + config.scenePath.stem().string();
  auto window = std::make_shared<window::GlfwWindow>(config.extent, title, options.loaderLibrary);
  options.surfaceExtensions = window->requiredInstanceExtensions();
  auto session = std::make_shared<WindowSession>(Key{}, std::move(title), window);
  session->context_ = gpu::Context::open(options);
  const VkSurfaceKHR surface = window->createSurface(gpu::instanceHandle(*session->context_));
  session->swapchain_ = gpu::makeSwapchain(session->context_, window, surface, config.swapchainPresentMode);
  return session;
}

WindowSession::WindowSession(Key, std::string title, std::shared_ptr<window::GlfwWindow> window)
    : title_(std::move(title)), window_(std::move(window)) {
  closeSignalled.store(false, std::memory_order_relaxed);
  previousInt = std::signal(SIGINT, &requestCloseOnSignal);
  previousTerm = std::signal(SIGTERM, &requestCloseOnSignal);
}

WindowSession::~WindowSession() {
  std::signal(SIGINT, previousInt);
  std::signal(SIGTERM, previousTerm);
}

gpu::SwapchainInfo WindowSession::swapchainInfo() const { return swapchain_->info(); }

bool WindowSession::keepRunning() {
  if (closeSignalled.load(std::memory_order_relaxed)) window_->requestClose();
  if (!window_->pollOpen()) closed_ = true;
  return !closed_;
}

std::optional<double> WindowSession::lastAcquireMs() const { return swapchain_->lastAcquireMs(); }

void WindowSession::frameDone(const FrameRecord& record) {
  const auto now = std::chrono::steady_clock::now();
  if (now - titleShown_ < kTitleInterval) return;
  titleShown_ = now;
  std::array<char, 256> text{};  // no allocation in the frame loop
  std::snprintf(text.data(), text.size(), "%s - %.2f ms", title_.c_str(),
                record.updateMs + record.renderMs + record.presentMs);
  window_->setTitle(text.data());
}

}  // namespace rt
