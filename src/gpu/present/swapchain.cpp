#include "gpu/present/swapchain.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rt::gpu {
namespace {

using Clock = std::chrono::steady_clock;
using Stage = vk::PipelineStageFlagBits;
using Access = vk::AccessFlagBits;
using Layout = vk::ImageLayout;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

vk::PresentModeKHR vulkanPresentMode(SwapchainPresentMode mode) {
  switch (mode) {
    case SwapchainPresentMode::fifo: return vk::PresentModeKHR::eFifo;
    case SwapchainPresentMode::mailbox: return vk::PresentModeKHR::eMailbox;
    case SwapchainPresentMode::immediate: return vk::PresentModeKHR::eImmediate;
  }
  return vk::PresentModeKHR::eFifo;
}

// The frame's bytes are shown as they are (the model applies no gamma
// curve), so only UNORM formats qualify: an SRGB image would encode them
// once more. Both byte orders are fine; the blit converts.
vk::SurfaceFormatKHR chooseFormat(const Device& device, const vk::raii::SurfaceKHR& surface) {
  const auto formats = device.physical().getSurfaceFormatsKHR(*surface);
  for (const vk::Format wanted : {vk::Format::eB8G8R8A8Unorm, vk::Format::eR8G8B8A8Unorm}) {
    const auto it = std::ranges::find_if(formats, [&](const vk::SurfaceFormatKHR& f) { return f.format == wanted; });
    const bool blittable = static_cast<bool>(device.physical().getFormatProperties(wanted).optimalTilingFeatures &
                                             vk::FormatFeatureFlagBits::eBlitDst);
    if (it != formats.end() && blittable) return *it;
  }
  throw DeviceUnavailable("the window's surface offers no 8-bit UNORM format (B8G8R8A8 or R8G8B8A8) that " +
                          device.info().name + " can blit into");
}

// FIFO is the one mode every surface supports: the fallback.
SwapchainPresentMode grantedMode(const Device& device, const vk::raii::SurfaceKHR& surface,
                                 SwapchainPresentMode requested) {
  const auto modes = device.physical().getSurfacePresentModesKHR(*surface);
  return std::ranges::find(modes, vulkanPresentMode(requested)) != modes.end() ? requested : SwapchainPresentMode::fifo;
}

std::uint32_t imageCountFor(const vk::SurfaceCapabilitiesKHR& caps) {
  // One more than the minimum, so that acquiring never waits for the
  // presentation engine to let go of the image it is showing.
  const std::uint32_t wanted = caps.minImageCount + 1;
  return caps.maxImageCount == 0 ? wanted : std::min(wanted, caps.maxImageCount);
}

// Where a frame of `frame` size lands in an image of `target` size: as large
// as fits with its aspect ratio, centred.
std::array<vk::Offset3D, 2> fittedRegion(Extent frame, vk::Extent2D target) {
  const double scale =
      std::min(static_cast<double>(target.width) / frame.width, static_cast<double>(target.height) / frame.height);
  const auto w = std::clamp(static_cast<std::int32_t>(std::lround(frame.width * scale)), 1,
                            static_cast<std::int32_t>(target.width));
  const auto h = std::clamp(static_cast<std::int32_t>(std::lround(frame.height * scale)), 1,
                            static_cast<std::int32_t>(target.height));
  const auto x = (static_cast<std::int32_t>(target.width) - w) / 2;
  const auto y = (static_cast<std::int32_t>(target.height) - h) / 2;
  return {vk::Offset3D{x, y, 0}, vk::Offset3D{x + w, y + h, 1}};
}

constexpr vk::ImageSubresourceLayers kColorLayer{vk::ImageAspectFlagBits::eColor, 0, 0, 1};
constexpr vk::ImageSubresourceRange kColorRange{vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1};

}  // namespace

Swapchain::Swapchain(std::shared_ptr<Context> context, std::shared_ptr<SurfaceHost> host, vk::raii::SurfaceKHR surface,
                     SwapchainPresentMode requested)
    : context_(std::move(context)),
      host_(std::move(host)),
      surface_(std::move(surface)),
      pool_(device().logical(), vk::CommandPoolCreateInfo{.flags = vk::CommandPoolCreateFlagBits::eResetCommandBuffer,
                                                          .queueFamilyIndex = device().queueFamily()}) {
  const Device& d = device();
  // The renderer's one queue presents too: it must be able to.
  if (!d.physical().getSurfaceSupportKHR(d.queueFamily(), *surface_)) {
    throw DeviceUnavailable("device " + d.info().name + " cannot present to the window's surface from queue family " +
                            std::to_string(d.queueFamily()));
  }
  if (!(d.physical().getSurfaceCapabilitiesKHR(*surface_).supportedUsageFlags & vk::ImageUsageFlagBits::eTransferDst)) {
    throw DeviceUnavailable("the window's swapchain images cannot be written by transfers on " + d.info().name);
  }
  format_ = chooseFormat(d, surface_);
  info_.requested = requested;
  info_.granted = grantedMode(d, surface_, requested);
  info_.surfaceFormat = vk::to_string(format_.format);
  presentMode_ = vulkanPresentMode(info_.granted);
  vk::raii::CommandBuffers buffers(d.logical(), vk::CommandBufferAllocateInfo{.commandPool = *pool_,
                                                                              .level = vk::CommandBufferLevel::ePrimary,
                                                                              .commandBufferCount = kFramesInFlight});
  for (auto& commands : buffers) {
    slots_.push_back({std::move(commands),
                      vk::raii::Fence(d.logical(), vk::FenceCreateInfo{.flags = vk::FenceCreateFlagBits::eSignaled}),
                      vk::raii::Semaphore(d.logical(), vk::SemaphoreCreateInfo{})});
  }
  // Made now, so that the metadata has its image count; a window minimised
  // already gets it at its first frame.
  (void)create();
}

VkInstance instanceHandle(const Context& context) { return *context.device().instance().get(); }

std::shared_ptr<Swapchain> makeSwapchain(std::shared_ptr<Context> context, std::shared_ptr<SurfaceHost> host,
                                         VkSurfaceKHR surface, SwapchainPresentMode requested) {
  vk::raii::SurfaceKHR owned(context->device().instance().get(), surface);
  return translateVulkanErrors("swapchain set-up", [&] {
    return std::make_shared<Swapchain>(std::move(context), std::move(host), std::move(owned), requested);
  });
}

Swapchain::~Swapchain() {
  try {
    device().logical().waitIdle();
  } catch (const vk::SystemError&) {
    // A lost device has nothing in flight that could outlive it.
  }
}

bool Swapchain::create() {
  const Device& d = device();
  const vk::SurfaceCapabilitiesKHR caps = d.physical().getSurfaceCapabilitiesKHR(*surface_);
  vk::Extent2D extent = caps.currentExtent;
  if (extent.width == std::numeric_limits<std::uint32_t>::max()) {  // the surface takes the swapchain's size
    const Extent window = host_->framebufferSize();
    extent = vk::Extent2D{
        std::clamp(static_cast<std::uint32_t>(window.width), caps.minImageExtent.width, caps.maxImageExtent.width),
        std::clamp(static_cast<std::uint32_t>(window.height), caps.minImageExtent.height, caps.maxImageExtent.height)};
  }
  if (extent.width == 0 || extent.height == 0) return false;  // minimised meanwhile
  const bool composeOpaque = static_cast<bool>(caps.supportedCompositeAlpha & vk::CompositeAlphaFlagBitsKHR::eOpaque);
  const vk::SwapchainCreateInfoKHR request{.surface = *surface_,
                                           .minImageCount = imageCountFor(caps),
                                           .imageFormat = format_.format,
                                           .imageColorSpace = format_.colorSpace,
                                           .imageExtent = extent,
                                           .imageArrayLayers = 1,
                                           .imageUsage = vk::ImageUsageFlagBits::eTransferDst,
                                           .imageSharingMode = vk::SharingMode::eExclusive,
                                           .preTransform = caps.currentTransform,
                                           .compositeAlpha = composeOpaque ? vk::CompositeAlphaFlagBitsKHR::eOpaque
                                                                           : vk::CompositeAlphaFlagBitsKHR::eInherit,
                                           .presentMode = presentMode_,
                                           .clipped = VK_TRUE,
                                           .oldSwapchain = *swapchain_};
  if (*swapchain_) ++info_.recreations;
  swapchain_ = vk::raii::SwapchainKHR(d.logical(), request);  // the old one goes after the new one exists
  extent_ = extent;
  images_.clear();
  for (const auto image : swapchain_.getImages()) images_.emplace_back(image);
  info_.imageCount = static_cast<std::uint32_t>(images_.size());
  renderDone_.clear();
  for (std::size_t i = 0; i < images_.size(); ++i) renderDone_.emplace_back(d.logical(), vk::SemaphoreCreateInfo{});
  return true;
}

std::optional<std::uint32_t> Swapchain::acquire() {
  const vk::raii::Device& d = device().logical();
  const FrameSlot& slot = slots_[slot_];
  Clock::time_point start = Clock::now();
  // This slot's last submission is done: its command buffer and semaphore are free.
  (void)d.waitForFences({*slot.done}, VK_TRUE, std::numeric_limits<std::uint64_t>::max());
  double waited = millisecondsSince(start);
  for (;;) {
    if (!*swapchain_ || outOfDate_) {
      if (!host_->waitWhileMinimised()) return std::nullopt;
      d.waitIdle();  // no image of the old swapchain is still being written or presented
      if (!create()) continue;
      outOfDate_ = false;
    }
    try {
      start = Clock::now();
      const auto [result, image] =
          swapchain_.acquireNextImage(std::numeric_limits<std::uint64_t>::max(), *slot.imageAvailable);
      waited += millisecondsSince(start);
      // Suboptimal: the image is ours and is shown; the swapchain is made anew after.
      if (result == vk::Result::eSuboptimalKHR) outOfDate_ = true;
      lastAcquireMs_ = waited;
      return image;
    } catch (const vk::OutOfDateKHRError&) {
      waited += millisecondsSince(start);
      outOfDate_ = true;
    }
  }
}

void Swapchain::recordBlit(const vk::raii::CommandBuffer& cb, std::uint32_t image, vk::Image source,
                           Extent extent) const {
  const vk::Image target = images_[image];
  // The acquire semaphore is waited for at the transfer stage; the old contents are not kept.
  constexpr ImageState kAcquired{Stage::eTransfer, {}, Layout::eUndefined};
  constexpr ImageState kWritten{Stage::eTransfer, Access::eTransferWrite, Layout::eTransferDstOptimal};
  imageBarrier(cb, target, kAcquired, kWritten);
  const std::array<vk::Offset3D, 2> region = fittedRegion(extent, extent_);
  const bool covers = region[0].x == 0 && region[0].y == 0 && region[1].x == static_cast<std::int32_t>(extent_.width) &&
                      region[1].y == static_cast<std::int32_t>(extent_.height);
  if (!covers) {  // black bars around a frame of another aspect ratio
    cb.clearColorImage(target, Layout::eTransferDstOptimal, vk::ClearColorValue(std::array{0.0f, 0.0f, 0.0f, 1.0f}),
                       kColorRange);
    imageBarrier(cb, target, kWritten, kWritten);
  }
  vk::ImageBlit blit{.srcSubresource = kColorLayer, .dstSubresource = kColorLayer};
  blit.srcOffsets[0] = vk::Offset3D{0, 0, 0};
  blit.srcOffsets[1] = vk::Offset3D{extent.width, extent.height, 1};
  blit.dstOffsets[0] = region[0];
  blit.dstOffsets[1] = region[1];
  // Nearest: at the frame's own size every pixel arrives unchanged.
  cb.blitImage(source, Layout::eTransferSrcOptimal, target, Layout::eTransferDstOptimal, blit, vk::Filter::eNearest);
  imageBarrier(cb, target, kWritten, {Stage::eBottomOfPipe, {}, Layout::ePresentSrcKHR});
}

void Swapchain::submitAndPresent(std::uint32_t image) {
  const FrameSlot& slot = slots_[slot_];
  const vk::Semaphore acquired = *slot.imageAvailable;
  const vk::Semaphore rendered = *renderDone_[image];
  const vk::CommandBuffer commands = *slot.commands;
  const vk::PipelineStageFlags waitStage = Stage::eTransfer;
  device().logical().resetFences({*slot.done});
  device().queue().submit(vk::SubmitInfo{.waitSemaphoreCount = 1,
                                         .pWaitSemaphores = &acquired,
                                         .pWaitDstStageMask = &waitStage,
                                         .commandBufferCount = 1,
                                         .pCommandBuffers = &commands,
                                         .signalSemaphoreCount = 1,
                                         .pSignalSemaphores = &rendered},
                          *slot.done);
  const vk::SwapchainKHR swapchain = *swapchain_;
  try {
    const vk::Result result = device().queue().presentKHR(vk::PresentInfoKHR{.waitSemaphoreCount = 1,
                                                                             .pWaitSemaphores = &rendered,
                                                                             .swapchainCount = 1,
                                                                             .pSwapchains = &swapchain,
                                                                             .pImageIndices = &image});
    if (result == vk::Result::eSuboptimalKHR) outOfDate_ = true;
  } catch (const vk::OutOfDateKHRError&) {
    outOfDate_ = true;
  }
  if (host_->takeResized()) outOfDate_ = true;
  ++info_.framesPresented;
  slot_ = (slot_ + 1) % kFramesInFlight;
}

}  // namespace rt::gpu
