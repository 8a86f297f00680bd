#pragma once
#include "core/image.h"
#include "render/render_options.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt {

// The render model evaluated in double precision: what the float sequential
// renderer must agree with (docs/render-model.md section 8) and what the golden images hold.
Image renderDoubleReference(const Scene& scene, const CameraFrame& camera, Extent extent, const RenderOptions& options);

}  // namespace rt
