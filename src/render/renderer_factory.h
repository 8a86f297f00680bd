#pragma once
#include <memory>
#include <stdexcept>

#include "render/present_setup.h"
#include "render/renderer.h"

namespace rt {

// Asked for a renderer this build does not have (yet).
class RendererUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `present` says where Present puts the frames; the GPU renderer needs its device.
std::unique_ptr<Renderer> makeRenderer(RendererKind kind, const PresentSetup& present = {});

}  // namespace rt
