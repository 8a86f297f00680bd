#pragma once
// The scalar ray-tracing kernel of docs/render-model.md sections 2-7:
// primary rays, shading, the bounce, both algorithms and the output, shared
// by the scalar renderers (float), the Embree kernel and the
// double-precision reference used by the tests. Everything here is inline
// and allocation-free: it runs per ray. The function names are the model's
// vocabulary, the same in the SIMD kernel and the shader (docs/render-model.md
// section 9).
#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "core/image.h"
#include "render/render_options.h"
#include "render/scalar/ray.h"
#include "render/scalar/sphere_query.h"
#include "render/shading_params.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt::kernel {

// Scene data a kernel reads per ray, converted once per scene (in prepare()).
template <typename Real>
struct ShadingInputs {
  std::span<const Sphere> spheres;
  const Bvh* bvh;      // the scene's hierarchy for the Accel::bvh variant; null otherwise
  Vec3<Real> toLight;  // -directionalLightDirection
  Vec3<Real> lightColor;
  Vec3<Real> ambientColor;
  Vec3<Real> background;
  Real reflectivity;
  Real shininess;
  Real specularStrength;
  int maxDepth;

  // The scene's spheres in this precision's form of the shading parameters.
  static ShadingInputs from(const Scene& scene, const Bvh* bvh = nullptr) {
    const ShadingParams p = shadingParamsOf(scene);
    return {scene.spheres,
            bvh,
            Vec3<Real>(p.toLight),
            Vec3<Real>(p.lightColor),
            Vec3<Real>(p.ambientColor),
            Vec3<Real>(p.background),
            static_cast<Real>(p.reflectivity),
            static_cast<Real>(p.shininess),
            static_cast<Real>(p.specularStrength),
            p.maxDepth};
  }
};

// The camera ray through pixel (x, y)'s centre (docs/render-model.md section 2).
template <typename Real>
inline Ray<Real> primaryRay(const CameraFrame& camera, Extent extent, int x, int y) {
  return {Vec3<Real>(camera.position), glm::normalize(primaryRayDirection<Real>(camera, extent, x, y))};
}

// Phong: ambient + diffuse + specular from one directional light (docs/render-model.md section 4).
template <typename Real>
inline Vec3<Real> localColor(const ShadingInputs<Real>& in, const RaycastHit<Real>& hit, const Vec3<Real>& direction,
                             const Vec3<Real>& sphereColor) {
  const Vec3<Real>& n = hit.normal;
  const Vec3<Real>& l = in.toLight;
  const Vec3<Real> ambient = in.ambientColor * sphereColor;
  const Vec3<Real> diffuse = std::max(glm::dot(n, l), Real(0)) * in.lightColor * sphereColor;
  const Vec3<Real> rr = -l - Real(2) * glm::dot(-l, n) * n;  // reflect(-l, n)
  // Clamped to [0, 1] (section 4): a hit reached from far away rounds its
  // position, the normal's length drifts above 1, and cos^shininess overflowed.
  const Real highlight = std::pow(std::clamp(glm::dot(rr, -direction), Real(0), Real(1)), in.shininess);
  return ambient + diffuse + in.specularStrength * highlight * in.lightColor;
}

// The bounce of docs/render-model.md section 5: offset origin, renormalised mirror direction.
template <typename Real>
inline Ray<Real> reflectedRay(const Ray<Real>& ray, const RaycastHit<Real>& hit) {
  const Vec3<Real>& d = ray.direction;
  const Vec3<Real>& n = hit.normal;
  return {hit.position + n * kEpsilon<Real>, glm::normalize(d - Real(2) * glm::dot(d, n) * n)};
}

// A single-pass bounce that hit a sphere: its light joins the colour, its
// colour filters the throughput, and the ray reflects.
template <typename Real>
inline void shadeBounce(const ShadingInputs<Real>& in, const RaycastHit<Real>& hit, Ray<Real>& ray, Vec3<Real>& color,
                        Vec3<Real>& throughput) {
  const Vec3<Real> sphereColor(in.spheres[static_cast<std::size_t>(hit.sphere)].color);
  color += throughput * localColor(in, hit, ray.direction, sphereColor);
  throughput *= in.reflectivity * sphereColor;
  ray = reflectedRay(ray, hit);
}

// Single-pass: accumulate colour and throughput on the way down.
template <typename Real, bool kBounceExit, Accel kAccel>
inline Vec3<Real> traceSinglePass(const ShadingInputs<Real>& in, Ray<Real> ray) {
  Vec3<Real> color(0);
  Vec3<Real> throughput(1);
  for (int depth = 0; depth < in.maxDepth; ++depth) {
    const RaycastHit<Real> hit = nearestHit<kAccel>(ray, in.spheres, in.bvh);
    if (!hit.hit()) {
      color += throughput * in.background;
      if constexpr (kBounceExit) break;
      // Without the early exit the dead ray is traced again (it misses
      // again) and adds nothing, as a masked SIMD lane would.
      throughput = Vec3<Real>(0);
      continue;
    }
    shadeBounce(in, hit, ray, color, throughput);
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

// One step of the two-pass backward pass: the light gathered behind
// segment `s` (`acc`) seen through it.
template <typename Real>
inline Vec3<Real> foldSegment(const ShadingInputs<Real>& in, const Vec3<Real>& acc, const PathSegment<Real>& s) {
  if (!s.hit.hit()) return in.background;
  return acc * in.reflectivity * s.sphereColor + localColor(in, s.hit, s.ray.direction, s.sphereColor);
}

// Two-pass (the thesis' original): the forward pass stores every ray, hit
// and sphere colour; the backward pass walks them from the last segment.
template <typename Real, bool kBounceExit, Accel kAccel>
inline Vec3<Real> traceTwoPass(const ShadingInputs<Real>& in, Ray<Real> ray,
                               std::span<PathSegment<Real>, kMaxDepthLimit> segments) {
  int count = 0;
  for (; count < in.maxDepth; ++count) {
    PathSegment<Real>& s = segments[static_cast<std::size_t>(count)];
    s.ray = ray;
    s.hit = nearestHit<kAccel>(ray, in.spheres, in.bvh);
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
  for (int i = count - 1; i >= 0; --i) acc = foldSegment(in, acc, segments[static_cast<std::size_t>(i)]);
  return acc;
}

// docs/render-model.md section 7: clamp to [0, 1], round(255 c), opaque, no gamma.
template <typename Real>
inline Rgba8 toRgba8(const Vec3<Real>& color) {
  const auto channel = [](Real v) {
    return static_cast<std::uint8_t>(std::clamp(v, Real(0), Real(1)) * Real(255) + Real(0.5));
  };
  return {channel(color.x), channel(color.y), channel(color.z), 255};
}

}  // namespace rt::kernel
