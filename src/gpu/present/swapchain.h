#pragma once
// The Present phase of a windowed run: a VkSwapchainKHR on the window's
// surface, frames in flight, and the copy of each frame into an acquired
// swapchain image.
#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "gpu/present/window_presentation.h"
#include "gpu/vulkan/context.h"
#include "gpu/vulkan/resources.h"

namespace rt::gpu {

// One swapchain on one surface of the context's device. Frames are handed
// over as an RGBA8 image in TRANSFER_SRC_OPTIMAL and blitted into the
// acquired image: the blit converts to the surface's byte order (usually
// BGRA, where a copy would swap red and blue) and fits the frame into the
// window, centred, whatever the window's size. A frame slot (command
// buffer, fence, acquire semaphore) is reused every kFramesInFlight frames,
// so the host prepares frame k+1 while frame k's copy runs.
class Swapchain {
 public:
  static constexpr std::uint32_t kFramesInFlight = 2;

  // Takes the surface (made by the window, on the context's instance).
  // Throws DeviceUnavailable when the device's queue cannot present to it or
  // it offers no 8-bit UNORM format that a blit can write.
  Swapchain(std::shared_ptr<Context> context, std::shared_ptr<SurfaceHost> host, vk::raii::SurfaceKHR surface,
            SwapchainPresentMode requested);
  ~Swapchain();  // waits until the device is idle: no frame still uses what goes
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  [[nodiscard]] const Device& device() const { return context_->device(); }
  [[nodiscard]] const SwapchainInfo& info() const { return info_; }
  // Host time the last present() waited for a swapchain image (its slot's
  // fence and vkAcquireNextImageKHR), in milliseconds.
  [[nodiscard]] double lastAcquireMs() const { return lastAcquireMs_; }

  // Presents one frame: waits for a free slot, acquires an image (making
  // the swapchain anew when it is out of date), calls
  // `recordSource(commandBuffer, slot)`, which records whatever leaves
  // `source` (an RGBA8 image of `extent`) in TRANSFER_SRC_OPTIMAL with its
  // writes available to transfers, then records the blit, submits and
  // queues the image for display. Returns false, showing nothing, when the
  // window was closed while minimised.
  template <typename RecordSource>
  bool present(vk::Image source, Extent extent, RecordSource&& recordSource) {
    const std::optional<std::uint32_t> image = acquire();
    if (!image) return false;
    const vk::raii::CommandBuffer& cb = slots_[slot_].commands;
    cb.begin(vk::CommandBufferBeginInfo{.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
    recordSource(cb, slot_);
    recordBlit(cb, *image, source, extent);
    cb.end();
    submitAndPresent(*image);
    return true;
  }

 private:
  struct FrameSlot {
    vk::raii::CommandBuffer commands;
    vk::raii::Fence done;                // signalled when the slot's submission completes
    vk::raii::Semaphore imageAvailable;  // signalled by the acquire, waited for by the submission
  };

  // The swapchain for the window's size now, replacing the old one; false while that size is zero.
  bool create();
  [[nodiscard]] std::optional<std::uint32_t> acquire();
  void recordBlit(const vk::raii::CommandBuffer& cb, std::uint32_t image, vk::Image source, Extent extent) const;
  void submitAndPresent(std::uint32_t image);

  std::shared_ptr<Context> context_;
  std::shared_ptr<SurfaceHost> host_;  // the window outlives its surface
  vk::raii::SurfaceKHR surface_;
  vk::SurfaceFormatKHR format_;
  vk::PresentModeKHR presentMode_;
  SwapchainInfo info_;
  vk::raii::CommandPool pool_;
  std::vector<FrameSlot> slots_;
  std::uint32_t slot_ = 0;
  vk::raii::SwapchainKHR swapchain_ = nullptr;
  vk::Extent2D extent_{};
  std::vector<vk::Image> images_;
  // One per image: a present may still wait for it when its slot comes round again.
  std::vector<vk::raii::Semaphore> renderDone_;
  bool outOfDate_ = false;
  double lastAcquireMs_ = 0.0;
};

}  // namespace rt::gpu
