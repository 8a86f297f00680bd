#pragma once
// The scalar ray-tracing kernel of docs/render-model.md sections 3-5, shared by
// the sequential renderer (float), the threads-only renderer and the
// double-precision reference used by the tests. Everything here is inline
// and allocation-free: it runs per ray.
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <span>

#include "core/image.h"
#include "model_constants.h"
#include "scene/scene.h"

namespace rt::kernel {

template <typename Real>
using Vec3 = glm::vec<3, Real>;

template <typename Real>
struct Ray {
  Vec3<Real> origin;
  Vec3<Real> direction;  // unit
};

template <typename Real>
struct RaycastHit {
  Vec3<Real> position;
  Vec3<Real> normal;
  Real distance;
  int sphere;  // index into the scene's spheres; -1 for a miss
  [[nodiscard]] bool hit() const { return sphere >= 0; }
};

// Scene data a kernel reads per ray, converted once per frame.
template <typename Real>
struct ShadingInputs {
  std::span<const Sphere> spheres;
  Vec3<Real> toLight;  // -directionalLightDirection
  Vec3<Real> lightColor;
  Vec3<Real> ambientColor;
  Vec3<Real> background;
  Real reflectivity;
  Real shininess;
  Real specularStrength;
  int maxDepth;

  static ShadingInputs from(const Scene& scene) {
    return {scene.spheres,
            -Vec3<Real>(scene.lightData.directionalLightDirection),
            Vec3<Real>(scene.lightData.directionalLightColor),
            Vec3<Real>(scene.lightData.ambientLightColor),
            Vec3<Real>(scene.render.background),
            static_cast<Real>(scene.render.reflectivity),
            static_cast<Real>(scene.render.shininess),
            static_cast<Real>(scene.render.specularStrength),
            scene.render.maxDepth};
  }
};

template <typename Real>
constexpr Real kEpsilon = static_cast<Real>(RT_HIT_EPSILON);

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

// Phong: ambient + diffuse + specular from one directional light (docs/render-model.md section 4).
template <typename Real>
inline Vec3<Real> localColor(const ShadingInputs<Real>& in, const RaycastHit<Real>& hit,
                             const Vec3<Real>& direction, const Vec3<Real>& sphereColor) {
  const Vec3<Real>& n = hit.normal;
  const Vec3<Real>& l = in.toLight;
  const Vec3<Real> ambient = in.ambientColor * sphereColor;
  const Vec3<Real> diffuse = std::max(glm::dot(n, l), Real(0)) * in.lightColor * sphereColor;
  const Vec3<Real> rr = -l - Real(2) * glm::dot(-l, n) * n;  // reflect(-l, n)
  const Real highlight = std::pow(std::max(glm::dot(rr, -direction), Real(0)), in.shininess);
  return ambient + diffuse + in.specularStrength * highlight * in.lightColor;
}

// The bounce of docs/render-model.md section 5: offset origin, renormalised mirror direction.
template <typename Real>
inline Ray<Real> reflectedRay(const Ray<Real>& ray, const RaycastHit<Real>& hit) {
  const Vec3<Real>& d = ray.direction;
  const Vec3<Real>& n = hit.normal;
  return {hit.position + n * kEpsilon<Real>, glm::normalize(d - Real(2) * glm::dot(d, n) * n)};
}

// Single-pass: accumulate colour and throughput on the way down.
template <typename Real, bool kBounceExit>
inline Vec3<Real> traceSinglePass(const ShadingInputs<Real>& in, Ray<Real> ray) {
  Vec3<Real> color(0);
  Vec3<Real> throughput(1);
  for (int depth = 0; depth < in.maxDepth; ++depth) {
    const RaycastHit<Real> hit = nearestHit(ray, in.spheres);
    if (!hit.hit()) {
      color += throughput * in.background;
      if constexpr (kBounceExit) break;
      // Without the early exit the dead ray is traced again (it misses
      // again) and adds nothing, as a masked SIMD lane would.
      throughput = Vec3<Real>(0);
      continue;
    }
    const Vec3<Real> sphereColor(in.spheres[static_cast<std::size_t>(hit.sphere)].color);
    color += throughput * localColor(in, hit, ray.direction, sphereColor);
    throughput *= in.reflectivity * sphereColor;
    ray = reflectedRay(ray, hit);
  }
  return color;
}

// One stored segment of the two-pass algorithm's forward pass.
template <typename Real>
struct PathSegment {
  Ray<Real> ray;
  RaycastHit<Real> hit;
  Vec3<Real> sphereColor;
};

// Two-pass (the thesis' original): the forward pass stores every ray, hit
// and sphere colour; the backward pass walks them from the last segment.
template <typename Real, bool kBounceExit>
inline Vec3<Real> traceTwoPass(const ShadingInputs<Real>& in, Ray<Real> ray,
                               std::span<PathSegment<Real>, kMaxDepthLimit> segments) {
  int count = 0;
  for (; count < in.maxDepth; ++count) {
    PathSegment<Real>& s = segments[static_cast<std::size_t>(count)];
    s.ray = ray;
    s.hit = nearestHit(ray, in.spheres);
    if (!s.hit.hit()) {
      if constexpr (kBounceExit) {
        ++count;
        break;
      }
      continue;  // a segment after a miss is a miss: the ray stays as it was
    }
    s.sphereColor = Vec3<Real>(in.spheres[static_cast<std::size_t>(s.hit.sphere)].color);
    ray = reflectedRay(ray, s.hit);
  }
  Vec3<Real> acc(0);
  for (int i = count - 1; i >= 0; --i) {
    const PathSegment<Real>& s = segments[static_cast<std::size_t>(i)];
    if (s.hit.hit()) {
      acc = acc * in.reflectivity * s.sphereColor + localColor(in, s.hit, s.ray.direction, s.sphereColor);
    } else {
      acc = in.background;
    }
  }
  return acc;
}

// Spec section 7: clamp to [0, 1], round(255 c), opaque, no gamma.
template <typename Real>
inline Rgba8 toRgba8(const Vec3<Real>& c) {
  const auto channel = [](Real v) {
    return static_cast<std::uint8_t>(std::clamp(v, Real(0), Real(1)) * Real(255) + Real(0.5));
  };
  return {channel(c.x), channel(c.y), channel(c.z), 255};
}

}  // namespace rt::kernel
