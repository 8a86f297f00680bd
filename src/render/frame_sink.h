#pragma once
#include <span>

#include "core/image.h"

namespace rt {

// Where a CPU renderer's Present phase hands each finished frame. The CPU
// renderers know only this interface; the Vulkan uploads into the present
// image (gpu::makeFrameUpload) and into a window (gpu::makeSwapchainUpload)
// implement it, and the app decides which sink, if any, a renderer gets.
class FrameSink {
 public:
  virtual ~FrameSink() = default;

  // Before the frame loop (outside the timed phases): sizes the destination
  // for frames of `extent`; a later call with another extent resizes it.
  virtual void prepare(Extent extent) = 0;
  // The Present phase: hands `frame` (extent.pixelCount() pixels) on.
  virtual void present(std::span<const Rgba8> frame) = 0;
  // What the last present() delivered, copied back into `target`.
  virtual void readBack(Image& target) = 0;
};

}  // namespace rt
