#pragma once
#include <memory>
#include <stdexcept>

#include "render/present_setup.h"
#include "render/renderer.h"

namespace rt {

// Asked for a renderer this build or this CPU does not have (exit code 2).
class RendererUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `settings` matter to the threaded and SIMD renderers only; `present` says
// where Present puts the frames (the GPU renderer needs its device).
std::unique_ptr<Renderer> makeRenderer(RendererKind kind, const ParallelSettings& settings = {},
                                       const PresentSetup& present = {});

}  // namespace rt
