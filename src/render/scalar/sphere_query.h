#pragma once
// The spatial query of the scalar kernel: the nearest sphere a ray hits.
// Brute force: every ray is tested against every sphere. This is the one
// place the scalar kernels ask the scene which sphere a ray meets; an
// acceleration structure replaces the loop in nearestHit().
#include <cmath>
#include <limits>
#include <span>

#include "render/scalar/ray.h"
#include "scene/scene.h"

namespace rt::kernel {

// Distance along the ray to one sphere, or a value <= EPS for no hit.
// Uses the cancellation-free discriminant of docs/render-model.md section 3.
template <typename Real>
inline Real intersectSphere(const Ray<Real>& ray, const Sphere& sphere) {
  const Vec3<Real> oc = ray.origin - Vec3<Real>(sphere.position);
  const Real b = glm::dot(oc, ray.direction);
  const Vec3<Real> f = oc - b * ray.direction;
  const Real r = static_cast<Real>(sphere.radius);
  const Real disc = r * r - glm::dot(f, f);
  if (disc < Real(0)) return Real(-1);
  const Real h = std::sqrt(disc);
  Real t = -b - h;
  if (t <= kEpsilon<Real>) t = -b + h;
  return t;
}

// The nearest hit over all spheres; on an exact tie the lower index wins.
template <typename Real>
inline RaycastHit<Real> nearestHit(const Ray<Real>& ray, std::span<const Sphere> spheres) {
  Real best = std::numeric_limits<Real>::infinity();
  int bestIndex = -1;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const Real t = intersectSphere(ray, spheres[i]);
    if (t > kEpsilon<Real> && t < best) {
      best = t;
      bestIndex = static_cast<int>(i);
    }
  }
  RaycastHit<Real> hit{};
  hit.sphere = bestIndex;
  if (bestIndex >= 0) {
    const Sphere& s = spheres[static_cast<std::size_t>(bestIndex)];
    hit.distance = best;
    hit.position = ray.origin + best * ray.direction;
    hit.normal = (hit.position - Vec3<Real>(s.position)) / static_cast<Real>(s.radius);
  }
  return hit;
}

}  // namespace rt::kernel
