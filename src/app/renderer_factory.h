#pragma once
#include <memory>

#include "app/device_setup.h"
#include "render/renderer.h"

namespace rt {

// The renderer a run asked for, wired to where its Present puts the frames:
// the GPU renderer on `present.device`; a CPU renderer built from its
// schema pair, with the device's frame upload as its sink in mode
// `upload`. `settings` matter to the renderers whose schema row accepts them.
std::unique_ptr<Renderer> makeRenderer(RendererKind kind, const ParallelSettings& settings = {},
                                       const PresentSetup& present = {});

}  // namespace rt
