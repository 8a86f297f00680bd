#pragma once
// The CPU renderers' Present phase on a Vulkan device, behind a header
// without Vulkan: the app hands it to a CPU renderer as its FrameSink.
#include <memory>

#include "render/frame_sink.h"

namespace rt::gpu {

class Context;

// The thesis' data path for the CPU renderers: the frame is copied into a
// mapped host-visible staging buffer, and vkCmdCopyBufferToImage moves it
// into the present image, as it moved into the swapchain image there. Its
// prepare() makes the present image and buffers (again only when the
// extent changes); present() is the staging copy, submit and wait; readBack()
// brings the present image's contents back (saved frames, tests). Throws
// std::invalid_argument without a context.
std::unique_ptr<FrameSink> makeFrameUpload(std::shared_ptr<Context> context);

}  // namespace rt::gpu
