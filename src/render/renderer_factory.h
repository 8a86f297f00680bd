#pragma once
#include <memory>
#include <stdexcept>

#include "render/renderer.h"

namespace rt {

// Asked for a renderer this build does not have (yet).
class RendererUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::unique_ptr<Renderer> makeRenderer(RendererKind kind);

}  // namespace rt
