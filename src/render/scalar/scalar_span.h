#pragma once
// Span level of the scalar kernel (pixel -> span -> frame): each variant
// (algorithm, bounce exit, accel) is its own instantiation, chosen before
// the frame, so no branch on the options runs per ray.
#include <span>
#include <stdexcept>

#include "render/render_options.h"
#include "render/scalar/scalar_model.h"
#include "scene/camera.h"

namespace rt {

// Pixels x0..x1-1 of row y (the schedulers hand out such spans).
template <typename Real, Algorithm kAlgorithm, bool kBounceExit, Accel kAccel>
void renderScalarSpan(const kernel::ShadingInputs<Real>& in, const CameraFrame& camera, Extent extent, int y, int x0,
                      int x1, std::span<Rgba8> row) {
  [[maybe_unused]] std::array<kernel::PathSegment<Real>, kMaxDepthLimit> segments;
  for (int x = x0; x < x1; ++x) {
    const kernel::Ray<Real> ray = kernel::primaryRay<Real>(camera, extent, x, y);
    kernel::Vec3<Real> color;
    if constexpr (kAlgorithm == Algorithm::two_pass) {
      color = kernel::traceTwoPass<Real, kBounceExit, kAccel>(in, ray, segments);
    } else {
      color = kernel::traceSinglePass<Real, kBounceExit, kAccel>(in, ray);
    }
    row[static_cast<std::size_t>(x)] = kernel::toRgba8(color);
  }
}

template <typename Real, Algorithm kAlgorithm, bool kBounceExit, Accel kAccel>
void renderScalarRow(const kernel::ShadingInputs<Real>& in, const CameraFrame& camera, Extent extent, int y,
                     std::span<Rgba8> row) {
  renderScalarSpan<Real, kAlgorithm, kBounceExit, kAccel>(in, camera, extent, y, 0, extent.width, row);
}

// Calls visit.template operator()<Algorithm, bool, Accel>() with the
// variant the options select: the algorithm, the bounce exit and --accel
// (the scalar kernels have no sphere or discriminant exit).
template <typename Visitor>
void visitScalarVariant(const RenderOptions& options, Visitor&& visit) {
  const auto withAccel = [&]<Algorithm kAlgorithm, bool kBounce>() {
    return options.accel == Accel::bvh ? visit.template operator()<kAlgorithm, kBounce, Accel::bvh>()
                                       : visit.template operator()<kAlgorithm, kBounce, Accel::none>();
  };
  const bool bounce = options.earlyExits.has(EarlyExit::bounce);
  switch (options.algorithm) {
    case Algorithm::single_pass:
      return bounce ? withAccel.template operator()<Algorithm::single_pass, true>()
                    : withAccel.template operator()<Algorithm::single_pass, false>();
    case Algorithm::two_pass:
      return bounce ? withAccel.template operator()<Algorithm::two_pass, true>()
                    : withAccel.template operator()<Algorithm::two_pass, false>();
  }
  throw std::logic_error("unknown algorithm");
}

}  // namespace rt
