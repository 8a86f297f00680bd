#pragma once
#include <memory>

#include "render/render_options.h"

namespace rt {

namespace gpu {
class Context;
}

// Where a renderer's Present phase hands its frames (issue 4): `upload`
// copies each frame into the device's present image, so present_ms means
// the same for every renderer; `none` leaves it where it was rendered.
struct PresentSetup {
  PresentMode mode = PresentMode::none;
  std::shared_ptr<gpu::Context> device;  // required by `upload` and by the GPU renderer
};

}  // namespace rt
