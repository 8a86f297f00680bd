#pragma once
// The spatial query of the scalar kernel: the nearest sphere a ray hits.
// Brute force tests every ray against every sphere; with a BVH
// (--accel bvh) only the spheres whose boxes the ray reaches are tested.
// This is the one place the scalar kernels ask which sphere a ray meets;
// which of the two is a template parameter, chosen once in prepare().
// The names are the model's vocabulary (docs/render-model.md section 9).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>

#include "render/accel/bvh.h"
#include "render/render_options.h"
#include "render/scalar/double_traversal_pad.h"
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

// The hit record of sphere `index` at distance `t` (or a miss for index -1).
template <typename Real>
inline RaycastHit<Real> hitRecord(const Ray<Real>& ray, std::span<const Sphere> spheres, Real t, int index) {
  RaycastHit<Real> hit{};
  hit.sphere = index;
  if (index >= 0) {
    const Sphere& s = spheres[static_cast<std::size_t>(index)];
    hit.distance = t;
    hit.position = ray.origin + t * ray.direction;
    hit.normal = (hit.position - Vec3<Real>(s.position)) / static_cast<Real>(s.radius);
    // docs/render-model.md section 4: a ray leaving the sphere sees its inside.
    if (glm::dot(ray.direction, hit.normal) > Real(0)) hit.normal = -hit.normal;
  }
  return hit;
}

// Brute force: the nearest hit over all spheres; on an exact tie the lower index wins.
template <typename Real>
inline RaycastHit<Real> nearestHitOfAll(const Ray<Real>& ray, std::span<const Sphere> spheres) {
  Real best = std::numeric_limits<Real>::infinity();
  int bestIndex = -1;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const Real t = intersectSphere(ray, spheres[i]);
    if (t > kEpsilon<Real> && t < best) {
      best = t;
      bestIndex = static_cast<int>(i);
    }
  }
  return hitRecord(ray, spheres, best, bestIndex);
}

// A component that is exactly zero becomes a tiny one of the same sign, so
// that the slab test's 0 * infinity never makes a NaN.
template <typename Real>
inline Vec3<Real> inverseDirection(const Vec3<Real>& direction) {
  const auto safe = [](Real c) { return std::abs(c) < Real(1e-30) ? std::copysign(Real(1e-30), c) : c; };
  return Real(1) / Vec3<Real>(safe(direction.x), safe(direction.y), safe(direction.z));
}

// Whether the ray may meet a sphere inside the box lo..hi, widened by
// `pad`, nearer than `best` (+ pad).
template <typename Real>
inline bool boxReachable(const glm::vec3& lo, const glm::vec3& hi, const Ray<Real>& ray, const Vec3<Real>& inverse,
                         Real pad, Real best) {
  const Vec3<Real> t0 = (Vec3<Real>(lo) - pad - ray.origin) * inverse;
  const Vec3<Real> t1 = (Vec3<Real>(hi) + pad - ray.origin) * inverse;
  const Vec3<Real> near = glm::min(t0, t1);
  const Vec3<Real> far = glm::max(t0, t1);
  const Real tmin = std::max({near.x, near.y, near.z});
  const Real tmax = std::min({far.x, far.y, far.z});
  return tmin <= tmax && tmax >= -pad && tmin <= best + pad;
}

// The pad of a ray from `origin` for this precision's sphere test:
// rt::traversalPad (render/accel/bvh.h, from the bound of |origin|) for
// float, the double reference's own (double_traversal_pad.h) for double.
template <typename Real>
inline Real traversalPad(const Bvh& bvh, const Vec3<Real>& origin) {
  const Vec3<Real> a = glm::abs(origin);
  const Real originMaxCoordinate = std::max({a.x, a.y, a.z});
  if constexpr (std::is_same_v<Real, double>) {
    return doubleTraversalPad(bvh, originMaxCoordinate);
  } else {
    return rt::traversalPad(bvh, static_cast<float>(originMaxCoordinate));
  }
}

// With a BVH: the same nearest hit as brute force, the same float test per
// sphere, spheres visited in tree order (so an exact tie is settled by the
// index, not by the order of the visit). Near child first, a fixed stack.
template <typename Real>
inline RaycastHit<Real> nearestHitInBvh(const Ray<Real>& ray, std::span<const Sphere> spheres, const Bvh& bvh) {
  const Vec3<Real> inverse = inverseDirection(ray.direction);
  const Real pad = traversalPad(bvh, ray.origin);
  Real best = std::numeric_limits<Real>::infinity();
  int bestIndex = -1;
  std::uint32_t stack[kBvhMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = bvh.nodes[stack[--top]];
    if (!boxReachable(node.lo, node.hi, ray, inverse, pad, best)) continue;
    if (!node.leaf()) {
      const bool negative = ray.direction[node.axis()] < Real(0);
      stack[top++] = node.first + (negative ? 0u : 1u);  // far child
      stack[top++] = node.first + (negative ? 1u : 0u);  // near child, visited next
      continue;
    }
    for (std::uint32_t k = node.first; k < node.first + node.count(); ++k) {
      const auto index = static_cast<int>(bvh.order[k]);
      const Real t = intersectSphere(ray, spheres[static_cast<std::size_t>(index)]);
      if (t > kEpsilon<Real> && (t < best || (t == best && index < bestIndex))) {
        best = t;
        bestIndex = index;
      }
    }
  }
  return hitRecord(ray, spheres, best, bestIndex);
}

// The kernels' one entry to the spatial query; kAccel is the compiled
// variant of --accel (with Accel::bvh, `bvh` is the scene's hierarchy).
template <Accel kAccel, typename Real>
inline RaycastHit<Real> nearestHit(const Ray<Real>& ray, std::span<const Sphere> spheres, const Bvh* bvh) {
  if constexpr (kAccel == Accel::bvh) {
    return nearestHitInBvh(ray, spheres, *bvh);
  } else {
    return nearestHitOfAll(ray, spheres);
  }
}

}  // namespace rt::kernel
