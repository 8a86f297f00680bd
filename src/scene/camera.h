#pragma once
#include <glm/vec3.hpp>

#include "core/image.h"
#include "scene/scene.h"

namespace rt {

// The animation's fixed time step (docs/render-model.md section 2, chosen): frame k shows
// the same picture whatever the frame took.
inline constexpr double kSecondsPerFrame = 1.0 / 60.0;

// The camera of one frame, ready for per-pixel ray generation in float.
struct CameraFrame {
  glm::vec3 position;
  glm::vec3 forward;
  glm::vec3 right;
  glm::vec3 up;
  float tanHalfFov;
};

// The largest |coordinate| the camera takes on its orbit (or at rest): a
// bound on where camera rays start, which sizes the traversal pad of the
// boxes that every ray of the scene is tested against (render/accel/bvh.h).
float cameraMaxCoordinate(const CameraSpec& camera);

// The Update phase: frame k's camera, computed from k directly (never
// accumulated), so it does not depend on timing or on earlier frames.
CameraFrame cameraAtFrame(const CameraSpec& spec, long long frame);

// Direction (not normalised) through pixel (x, y)'s centre; docs/render-model.md section 2.
// Templated on the precision so the double-precision reference shares it.
template <typename Real>
glm::vec<3, Real> primaryRayDirection(const CameraFrame& cam, Extent extent, int x, int y) {
  using V = glm::vec<3, Real>;
  const Real w = static_cast<Real>(extent.width);
  const Real h = static_cast<Real>(extent.height);
  const Real th = static_cast<Real>(cam.tanHalfFov);
  const Real u = (Real(2) * (static_cast<Real>(x) + Real(0.5)) / w - Real(1)) * th * (w / h);
  const Real v = (Real(1) - Real(2) * (static_cast<Real>(y) + Real(0.5)) / h) * th;
  return V(cam.forward) + u * V(cam.right) + v * V(cam.up);
}

}  // namespace rt
