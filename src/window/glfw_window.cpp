#include "window/glfw_window.h"

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>
#include <utility>

// After vulkan_core.h (through the header): declares glfwCreateWindowSurface.
#include <GLFW/glfw3.h>

namespace rt::window {
namespace {

constexpr bool kGlfwTakesLoader = GLFW_VERSION_MAJOR > 3 || (GLFW_VERSION_MAJOR == 3 && GLFW_VERSION_MINOR >= 4);

// GLFW reports failures through a callback; the last one goes into the exception.
thread_local std::string lastGlfwError;

void rememberError(int code, const char* description) {
  lastGlfwError =
      std::string(description ? description : "unknown error") + " (GLFW error " + std::to_string(code) + ")";
}

std::string displayNote() {
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((x11 == nullptr || *x11 == '\0') && (wayland == nullptr || *wayland == '\0')) {
    return "; there is no display (DISPLAY and WAYLAND_DISPLAY are unset): run without --window, "
           "or under a virtual X server (xvfb-run -a raytracer --window ...)";
  }
  return "";
}

[[noreturn]] void fail(const std::string& what) {
  throw gpu::WindowUnavailable("cannot open a window: " + what + ": " + lastGlfwError + displayNote());
}

// The run's Vulkan loader, open for GLFW (3.4+) as long as the window lives.
struct LoaderHandle {
  struct Closer {
    void operator()(void* handle) const { dlclose(handle); }
  };
  std::unique_ptr<void, Closer> handle;
};

}  // namespace

struct GlfwWindow::State {
  LoaderHandle loader;
  GLFWwindow* window = nullptr;
  bool resized = false;

  ~State() {
    if (window) glfwDestroyWindow(window);
    glfwTerminate();
  }
};

GlfwWindow::GlfwWindow(Extent size, const std::string& title, const std::string& loaderLibrary)
    : state_(std::make_unique<State>()) {
  glfwSetErrorCallback(&rememberError);
  if constexpr (kGlfwTakesLoader) {
    state_->loader.handle.reset(dlopen(loaderLibrary.c_str(), RTLD_NOW | RTLD_LOCAL));
    if (!state_->loader.handle) throw gpu::WindowUnavailable("cannot open a window: no Vulkan loader " + loaderLibrary);
#if GLFW_VERSION_MAJOR > 3 || (GLFW_VERSION_MAJOR == 3 && GLFW_VERSION_MINOR >= 4)
    glfwInitVulkanLoader(
        reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(state_->loader.handle.get(), "vkGetInstanceProcAddr")));
#endif
  }
  if (glfwInit() != GLFW_TRUE) fail("GLFW cannot start");
  if (glfwVulkanSupported() != GLFW_TRUE) fail("GLFW finds no Vulkan loader");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  state_->window = glfwCreateWindow(size.width, size.height, title.c_str(), nullptr, nullptr);
  if (!state_->window) fail("glfwCreateWindow failed");
  glfwSetWindowUserPointer(state_->window, state_.get());
  glfwSetKeyCallback(state_->window, [](GLFWwindow* w, int key, int /*scancode*/, int action, int /*mods*/) {
    if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
  });
  glfwSetFramebufferSizeCallback(state_->window, [](GLFWwindow* w, int /*width*/, int /*height*/) {
    static_cast<State*>(glfwGetWindowUserPointer(w))->resized = true;
  });
}

GlfwWindow::~GlfwWindow() = default;

std::vector<std::string> GlfwWindow::requiredInstanceExtensions() const {
  std::uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (names == nullptr) fail("no Vulkan surface extensions for this window system");
  return {names, names + count};
}

VkSurfaceKHR GlfwWindow::createSurface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  const VkResult result = glfwCreateWindowSurface(instance, state_->window, nullptr, &surface);
  if (result != VK_SUCCESS) fail("glfwCreateWindowSurface returned VkResult " + std::to_string(result));
  return surface;
}

bool GlfwWindow::pollOpen() {
  glfwPollEvents();
  return glfwWindowShouldClose(state_->window) != GLFW_TRUE;
}

void GlfwWindow::requestClose() { glfwSetWindowShouldClose(state_->window, GLFW_TRUE); }

void GlfwWindow::setTitle(const char* title) { glfwSetWindowTitle(state_->window, title); }

Extent GlfwWindow::framebufferSize() const {
  Extent size;
  glfwGetFramebufferSize(state_->window, &size.width, &size.height);
  return size;
}

bool GlfwWindow::waitWhileMinimised() {
  for (Extent size = framebufferSize(); size.width == 0 || size.height == 0; size = framebufferSize()) {
    if (glfwWindowShouldClose(state_->window) == GLFW_TRUE) return false;
    glfwWaitEvents();
  }
  return glfwWindowShouldClose(state_->window) != GLFW_TRUE;
}

bool GlfwWindow::takeResized() { return std::exchange(state_->resized, false); }

}  // namespace rt::window
