#include "scene/camera.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <numbers>

namespace rt {
namespace {

// Right-handed rotation about +Y by `angle` radians (docs/render-model.md section 2).
glm::dvec3 rotateAboutY(glm::dvec3 v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}

}  // namespace

float cameraMaxCoordinate(const CameraSpec& camera) {
  const glm::dvec3 p = glm::abs(camera.position);
  double bound = std::max({p.x, p.y, p.z});
  if (camera.orbits() && camera.focusPoint) {
    // On its orbit the camera stays at its distance from the focus point.
    const glm::dvec3 f = glm::abs(*camera.focusPoint);
    bound = std::max(bound, std::max({f.x, f.y, f.z}) + glm::length(camera.position - *camera.focusPoint));
  }
  return static_cast<float>(bound);
}

CameraFrame cameraAtFrame(const CameraSpec& spec, long long frame) {
  glm::dvec3 position = spec.position;
  glm::dvec3 forward = spec.forward;
  if (spec.orbits()) {
    const double angle = spec.orbitVelocity * static_cast<double>(frame) * kSecondsPerFrame;
    position = *spec.focusPoint + rotateAboutY(spec.position - *spec.focusPoint, angle);
    forward = glm::normalize(*spec.focusPoint - position);
  }
  const glm::dvec3 worldUp(0.0, 1.0, 0.0);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, worldUp));
  const glm::dvec3 up = glm::cross(right, forward);
  const double tanHalfFov = std::tan(spec.fov * std::numbers::pi / 180.0 / 2.0);
  return CameraFrame{glm::vec3(position), glm::vec3(forward), glm::vec3(right), glm::vec3(up),
                     static_cast<float>(tanHalfFov)};
}

}  // namespace rt
