#pragma once
// Span level of the scalar kernel (pixel -> span -> frame): each variant is
// its own instantiation, chosen before the frame, so no branch on the
// options runs per ray.
#include <span>
#include <stdexcept>

#include "render/render_options.h"
#include "render/scalar/scalar_model.h"
#include "scene/camera.h"

namespace rt {

// Pixels x0..x1-1 of row y (the schedulers hand out such spans).
template <typename Real, Algorithm kAlgorithm, bool kBounceExit>
void renderScalarSpan(const kernel::ShadingInputs<Real>& in, const CameraFrame& camera, Extent extent, int y,
                      int x0, int x1, std::span<Rgba8> row) {
  const kernel::Vec3<Real> origin(camera.position);
  [[maybe_unused]] std::array<kernel::PathSegment<Real>, kMaxDepthLimit> segments;
  for (int x = x0; x < x1; ++x) {
    const kernel::Ray<Real> ray{origin, glm::normalize(primaryRayDirection<Real>(camera, extent, x, y))};
    kernel::Vec3<Real> color;
    if constexpr (kAlgorithm == Algorithm::two_pass) {
      color = kernel::traceTwoPass<Real, kBounceExit>(in, ray, segments);
    } else {
      color = kernel::traceSinglePass<Real, kBounceExit>(in, ray);
    }
    row[static_cast<std::size_t>(x)] = kernel::toRgba8(color);
  }
}

template <typename Real, Algorithm kAlgorithm, bool kBounceExit>
void renderScalarRow(const kernel::ShadingInputs<Real>& in, const CameraFrame& camera, Extent extent, int y,
                     std::span<Rgba8> row) {
  renderScalarSpan<Real, kAlgorithm, kBounceExit>(in, camera, extent, y, 0, extent.width, row);
}

// Calls visit.template operator()<Algorithm, bool>() with the variant the options select.
template <typename Visitor>
void visitScalarVariant(const RenderOptions& options, Visitor&& visit) {
  const bool bounce = options.earlyExits.has(EarlyExit::bounce);
  switch (options.algorithm) {
    case Algorithm::single_pass:
      return bounce ? visit.template operator()<Algorithm::single_pass, true>()
                    : visit.template operator()<Algorithm::single_pass, false>();
    case Algorithm::two_pass:
      return bounce ? visit.template operator()<Algorithm::two_pass, true>()
                    : visit.template operator()<Algorithm::two_pass, false>();
  }
  throw std::logic_error("unknown algorithm");
}

}  // namespace rt
