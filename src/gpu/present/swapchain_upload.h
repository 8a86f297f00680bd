#pragma once
// The CPU renderers' Present phase in a window, behind a header without
// Vulkan: the app hands it to a CPU renderer as its FrameSink.
#include <memory>

#include "render/frame_sink.h"

namespace rt::gpu {

class Swapchain;

// The thesis' data path into a window: the frame is copied into a mapped
// staging buffer (one per frame in flight), vkCmdCopyBufferToImage moves it
// into an RGBA8 image on the device, and the swapchain blits that into the
// acquired image and presents it: present() is acquire, staging copy,
// upload, blit, present. readBack() returns the frame last handed to the
// window, from its staging buffer; the sink's end waits for the frames in
// flight. Throws std::invalid_argument without a swapchain.
std::unique_ptr<FrameSink> makeSwapchainUpload(std::shared_ptr<Swapchain> swapchain);

}  // namespace rt::gpu
