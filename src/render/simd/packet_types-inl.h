// The packet types of the SIMD kernel (the thesis' Vec3_x4, Ray_x4,
// RaycastHit_x4) and their arithmetic, one Highway lane per pixel. Compiled
// once per target, hence the toggling include guard instead of #pragma once.
#if defined(RT_RENDER_SIMD_PACKET_TYPES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RT_RENDER_SIMD_PACKET_TYPES_INL_H_
#undef RT_RENDER_SIMD_PACKET_TYPES_INL_H_
#else
#define RT_RENDER_SIMD_PACKET_TYPES_INL_H_
#endif

#include <hwy/highway.h>

#include <limits>

#include "model_constants.h"
#include "render/simd/packet_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace rt::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D>
using VecF = hn::Vec<D>;
template <class D>
using MaskF = hn::Mask<D>;

constexpr float kEpsilon = static_cast<float>(RT_HIT_EPSILON);

// ---- Packet types (the thesis' Vec3_x4, Ray_x4, RaycastHit_x4) ----------

template <class D>
struct Vec3x {
  VecF<D> x, y, z;
};

template <class D>
struct RayX {
  Vec3x<D> origin;
  Vec3x<D> direction;  // unit in every lane
};

template <class D>
struct HitX {
  MaskF<D> hit;  // lanes that hit a sphere; the other lanes hold junk
  Vec3x<D> position;
  Vec3x<D> normal;
  VecF<D> distance;
  Vec3x<D> sphereColor;
};

// ---- Vec3x arithmetic: the same evaluation order as glm's ---------------

template <class D>
HWY_INLINE Vec3x<D> Broadcast(D d, const Float3& v) {
  return {hn::Set(d, v[0]), hn::Set(d, v[1]), hn::Set(d, v[2])};
}
template <class D>
HWY_INLINE Vec3x<D> operator+(const Vec3x<D>& a, const Vec3x<D>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class D>
HWY_INLINE Vec3x<D> operator-(const Vec3x<D>& a, const Vec3x<D>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class D>
HWY_INLINE Vec3x<D> operator*(const Vec3x<D>& a, const Vec3x<D>& b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
template <class D>
HWY_INLINE Vec3x<D> operator*(VecF<D> s, const Vec3x<D>& v) {
  return {s * v.x, s * v.y, s * v.z};
}
template <class D>
HWY_INLINE Vec3x<D> operator/(const Vec3x<D>& v, VecF<D> s) {
  return {v.x / s, v.y / s, v.z / s};
}
template <class D>
HWY_INLINE VecF<D> Dot(const Vec3x<D>& a, const Vec3x<D>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
// glm::normalize: v * (1 / sqrt(dot(v, v))).
template <class D>
HWY_INLINE Vec3x<D> Normalize(D d, const Vec3x<D>& v) {
  return (hn::Set(d, 1.0f) / hn::Sqrt(Dot(v, v))) * v;
}
template <class D>
HWY_INLINE Vec3x<D> Select(MaskF<D> m, const Vec3x<D>& yes, const Vec3x<D>& no) {
  return {hn::IfThenElse(m, yes.x, no.x), hn::IfThenElse(m, yes.y, no.y), hn::IfThenElse(m, yes.z, no.z)};
}

}  // namespace rt::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
