#pragma once
// What the two GPU renderers (GPURenderer, the compute shader, and
// GpuRtRenderer, the ray-tracing pipeline) share: the device, the Present
// path with its window, the commands every phase is recorded in, the last
// frame's gpu_ms, and the Present phase and readback of the image their
// shaders write (ShaderOutput). Vulkan stays out of this header, as out of
// theirs.
#include <memory>
#include <optional>
#include <string>

#include "render/renderer.h"

namespace rt::gpu {

class Context;
class Device;
class FrameCommands;
class ShaderOutput;
class Swapchain;

class DeviceRenderer : public Renderer {
 public:
  ~DeviceRenderer() override;

  // Present: the frame into the present image (upload), into the window's
  // next image (window), or nowhere (none).
  void present() final;
  void readPresented(Image& target) final;
  [[nodiscard]] std::optional<double> lastGpuMs() const final { return gpuMs_; }

 protected:
  // `name` names the renderer in messages ("GPU renderer"); `present` picks
  // the Present path, `window` is the swapchain of mode window. Throws
  // std::invalid_argument without a device, or for mode window without a
  // swapchain.
  DeviceRenderer(std::string name, std::shared_ptr<Context> context, PresentMode present,
                 std::shared_ptr<Swapchain> window);

  [[nodiscard]] const Device& device() const;
  [[nodiscard]] PresentMode presentMode() const { return presentMode_; }
  [[nodiscard]] FrameCommands& frames() { return *frames_; }
  // What every GPU renderer's info() starts from: the device schedules the
  // work, so no threads and no lanes are recorded.
  [[nodiscard]] static RendererInfo deviceInfo(RendererKind kind);

  // What every prepare() does first, before it replaces the scene's
  // objects: refuses a scene without spheres (std::invalid_argument), waits
  // for a window's frames in flight, which still read those objects (a
  // Vulkan failure is a DeviceError naming the renderer's prepare), and
  // forgets the last gpu_ms.
  void beginPrepare(const Scene& scene);
  // With a window, waits for the frames in flight before the renderer's
  // destructor frees what they read (a lost device runs nothing that could
  // still read it).
  void waitForWindowAtEnd() noexcept;

  // The image the prepared scene's shaders write; throws std::logic_error
  // before prepare().
  virtual ShaderOutput& output() = 0;

  std::optional<double> gpuMs_;  // the last render()'s device time, as lastGpuMs() reports it

 private:
  std::string name_;
  std::shared_ptr<Context> context_;  // declared first of the Vulkan objects, so destroyed last
  PresentMode presentMode_;
  std::shared_ptr<Swapchain> window_;  // mode window only
  std::unique_ptr<FrameCommands> frames_;
};

}  // namespace rt::gpu
