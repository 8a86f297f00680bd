#include "render/cpu_renderer.h"

#include <algorithm>
#include <stdexcept>

#include "gpu/frame_upload.h"

namespace rt {

CPURenderer::CPURenderer() = default;
CPURenderer::~CPURenderer() = default;

void CPURenderer::setPresentSetup(PresentSetup setup) {
  if (setup.mode == PresentMode::upload && !setup.device) {
    throw std::invalid_argument("present mode 'upload' needs a Vulkan device");
  }
  presentSetup_ = std::move(setup);
  upload_.reset();
}

void CPURenderer::prepare(const Scene& scene, Extent extent, const RenderOptions& options) {
  scene_ = &scene;
  options_ = options;
  if (frame_.extent() != extent) frame_ = Image(extent);
  if (presentSetup_.mode == PresentMode::upload && (!upload_ || upload_->extent() != extent)) {
    upload_.reset();  // the old present image goes before the new one is made
    upload_ = std::make_unique<gpu::FrameUpload>(presentSetup_.device, extent);
  }
}

void CPURenderer::present() {
  // Mode none: the frame stays in the working buffer; nothing to do.
  if (upload_) upload_->present(frame_.pixels());
}

void CPURenderer::readPresented(Image& target) {
  if (target.extent() != frame_.extent()) throw std::logic_error("readPresented: target extent differs from the frame's");
  if (upload_) {
    upload_->readBack(target);  // what really reached the present image
  } else {
    std::ranges::copy(frame_.pixels(), target.pixels().begin());
  }
}

}  // namespace rt
