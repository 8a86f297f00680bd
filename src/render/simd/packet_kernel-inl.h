// The SIMD ray-tracing kernel: docs/render-model.md sections 3-7 on packets of
// horizontally adjacent pixels, one Highway lane per pixel. Compiled once
// per target (packet_kernels.cc includes it through foreach_target.h), hence
// the toggling include guard instead of #pragma once.
//
// It mirrors scalar/scalar_model.h operation for operation (same formulas, same
// evaluation order, a masked lane where the scalar code branches), so the
// image agrees with the sequential renderer; the only intended differences
// are fused multiply-adds in the sphere test and the power function. The
// functions carry the scalar kernel's names in Highway's case, the packet
// types the suffix X (docs/render-model.md section 9).

#if defined(RT_RENDER_SIMD_PACKET_KERNEL_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RT_RENDER_SIMD_PACKET_KERNEL_INL_H_
#undef RT_RENDER_SIMD_PACKET_KERNEL_INL_H_
#else
#define RT_RENDER_SIMD_PACKET_KERNEL_INL_H_
#endif

#include <hwy/cache_control.h>
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "model_constants.h"
#include "render/scalar/scalar_model.h"  // the f16 kernel's float steps: primaryRayDirection, toRgba8
#include "render/simd/packet_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace rt::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D>
using VecF = hn::Vec<D>;
template <class D>
using MaskF = hn::Mask<D>;
template <class D>
using LaneT = hn::TFromD<D>;
// A lane type of the half-precision kernel (hwy::float16_t), not float.
template <class T>
inline constexpr bool kHalfLane = sizeof(T) != sizeof(float);
// Packets of f16 lanes.
template <class D>
inline constexpr bool kHalfLanes = kHalfLane<LaneT<D>>;

constexpr float kEpsilon = static_cast<float>(RT_HIT_EPSILON);

// Whether this target computes in f16 natively (Highway 1.2 and newer:
// AVX3_SPR with GCC, NEON_BF16, NEON built with FP16); only then is the
// half-precision kernel compiled (docs/render-model.md section 10). Before
// 1.2, HWY_HAVE_FLOAT16 meant f16 loads and conversions only.
#undef RT_SIMD_NATIVE_F16
#if (HWY_MAJOR > 1 || HWY_MINOR >= 2) && HWY_HAVE_FLOAT16
#define RT_SIMD_NATIVE_F16 1
#else
#define RT_SIMD_NATIVE_F16 0
#endif

// A float value of the model in the lane type T: rounded to f16 once, or
// kept as it is.
template <class T>
HWY_INLINE T LaneValue(float value) {
#if RT_SIMD_NATIVE_F16
  if constexpr (kHalfLane<T>) {
    return hwy::F16FromF32(value);
  } else {
    return value;
  }
#else
  return value;
#endif
}

// A float value of the model in every lane.
template <class D>
HWY_INLINE VecF<D> Splat(D d, float value) {
  return hn::Set(d, LaneValue<LaneT<D>>(value));
}

// ---- Holding vectors (docs/render-model.md section 9) -------------------
// Scalable targets' vectors (SVE, RVV) are sizeless types: no struct
// member, no array element. There the packet types hold each vector's lanes
// in memory, stored where a packet is built and loaded where it is read;
// on every other target they hold the vector itself, and Hold and Get are
// the identity. Arithmetic uses Highway's named operations (Add, Lt, ...),
// since scalable vectors have no operators either.

// The most lanes a packet has: lane masks travel as 32 bits (LaneBits), and
// no SVE machine is wider than 512 bits (16 float lanes).
inline constexpr std::size_t kMaxPacketLanes = 32;

// The packet of a target's widest vector, at most kMaxPacketLanes lanes of T.
template <class T>
using NativeTag = hn::CappedTag<T, kMaxPacketLanes>;

#if HWY_HAVE_SCALABLE
template <class D>
struct HeldF {
  HWY_ALIGN LaneT<D> lanes[hn::MaxLanes(D())];
};
template <class D>
struct HeldM {
  std::uint8_t bits[8];  // StoreMaskBits' layout (it may write 8 bytes, whatever the lane count)
};
template <class D>
HWY_INLINE HeldF<D> Hold(D d, VecF<D> v) {
  HeldF<D> held;
  hn::Store(v, d, held.lanes);
  return held;
}
template <class D>
HWY_INLINE HeldM<D> HoldMask(D d, MaskF<D> m) {
  HeldM<D> held{};
  hn::StoreMaskBits(d, m, held.bits);
  return held;
}
template <class D>
HWY_INLINE VecF<D> Get(const HeldF<D>& held) {
  return hn::Load(D(), held.lanes);
}
template <class D>
HWY_INLINE MaskF<D> Get(const HeldM<D>& held) {
  return hn::LoadMaskBits(D(), held.bits);
}
#else
template <class D>
using HeldF = VecF<D>;
template <class D>
using HeldM = MaskF<D>;
template <class D>
HWY_INLINE VecF<D> Hold(D, VecF<D> v) {
  return v;
}
template <class D>
HWY_INLINE MaskF<D> HoldMask(D, MaskF<D> m) {
  return m;
}
template <class V>
HWY_INLINE V Get(V v) {
  return v;
}
#endif

// ---- Packet types (the thesis' Vec3_x4, Ray_x4, RaycastHit_x4) ----------
// The scalar kernel's Vec3, Ray and RaycastHit (scalar/ray.h), one lane per pixel.
// Always built whole, never default-constructed and then assigned: GCC
// compiles an implicit default constructor without the target's attributes,
// and with Highway 1.0 on NEON (whose target adds +crypto) it then cannot
// inline the vectors' always-inline constructors, which fails the build.

template <class D>
struct Vec3x {
  HeldF<D> x, y, z;
};

template <class D>
struct RayX {
  Vec3x<D> origin;
  Vec3x<D> direction;  // unit in every lane
};

template <class D>
struct RaycastHitX {
  HeldM<D> hit;  // lanes that hit a sphere; the other lanes hold junk
  Vec3x<D> position;
  Vec3x<D> normal;
  HeldF<D> distance;
  Vec3x<D> sphereColor;
};

// A Vec3x of three vectors, held (the packet types' only constructor).
template <class D>
HWY_INLINE Vec3x<D> Vec3Of(D d, VecF<D> x, VecF<D> y, VecF<D> z) {
  return {Hold(d, x), Hold(d, y), Hold(d, z)};
}

// ---- Vec3x arithmetic: the same evaluation order as glm's ---------------

template <class D>
HWY_INLINE Vec3x<D> Broadcast(D d, const glm::vec3& v) {
  return Vec3Of(d, Splat(d, v[0]), Splat(d, v[1]), Splat(d, v[2]));
}
template <class D>
HWY_INLINE Vec3x<D> Zero3(D d) {
  return Vec3Of(d, hn::Zero(d), hn::Zero(d), hn::Zero(d));
}
template <class D>
HWY_INLINE Vec3x<D> Add(D d, const Vec3x<D>& a, const Vec3x<D>& b) {
  return Vec3Of(d, hn::Add(Get(a.x), Get(b.x)), hn::Add(Get(a.y), Get(b.y)), hn::Add(Get(a.z), Get(b.z)));
}
template <class D>
HWY_INLINE Vec3x<D> Sub(D d, const Vec3x<D>& a, const Vec3x<D>& b) {
  return Vec3Of(d, hn::Sub(Get(a.x), Get(b.x)), hn::Sub(Get(a.y), Get(b.y)), hn::Sub(Get(a.z), Get(b.z)));
}
template <class D>
HWY_INLINE Vec3x<D> Mul(D d, const Vec3x<D>& a, const Vec3x<D>& b) {
  return Vec3Of(d, hn::Mul(Get(a.x), Get(b.x)), hn::Mul(Get(a.y), Get(b.y)), hn::Mul(Get(a.z), Get(b.z)));
}
template <class D>
HWY_INLINE Vec3x<D> Scale(D d, VecF<D> s, const Vec3x<D>& v) {
  return Vec3Of(d, hn::Mul(s, Get(v.x)), hn::Mul(s, Get(v.y)), hn::Mul(s, Get(v.z)));
}
template <class D>
HWY_INLINE Vec3x<D> Divide(D d, const Vec3x<D>& v, VecF<D> s) {
  return Vec3Of(d, hn::Div(Get(v.x), s), hn::Div(Get(v.y), s), hn::Div(Get(v.z), s));
}
template <class D>
HWY_INLINE VecF<D> Dot(const Vec3x<D>& a, const Vec3x<D>& b) {
  return hn::Add(hn::Add(hn::Mul(Get(a.x), Get(b.x)), hn::Mul(Get(a.y), Get(b.y))), hn::Mul(Get(a.z), Get(b.z)));
}
// glm::normalize: v * (1 / sqrt(dot(v, v))).
template <class D>
HWY_INLINE Vec3x<D> Normalize(D d, const Vec3x<D>& v) {
  return Scale(d, hn::Div(Splat(d, 1.0f), hn::Sqrt(Dot(v, v))), v);
}
template <class D>
HWY_INLINE Vec3x<D> Select(D d, MaskF<D> m, const Vec3x<D>& yes, const Vec3x<D>& no) {
  return Vec3Of(d, hn::IfThenElse(m, Get(yes.x), Get(no.x)), hn::IfThenElse(m, Get(yes.y), Get(no.y)),
                hn::IfThenElse(m, Get(yes.z), Get(no.z)));
}

// ---- Counters (--counters) ------------------------------------------------

// Lanes of a mask as bits, lane 0 lowest (packets have at most kMaxPacketLanes lanes).
template <class D>
HWY_INLINE std::uint32_t LaneBits(D d, MaskF<D> m) {
  static_assert(hn::MaxLanes(D()) <= kMaxPacketLanes, "lane masks are kept in 32 bits");
  std::uint8_t bytes[8] = {};
  hn::StoreMaskBits(d, m, bytes);
  return std::uint32_t{bytes[0]} | std::uint32_t{bytes[1]} << 8 | std::uint32_t{bytes[2]} << 16 |
         std::uint32_t{bytes[3]} << 24;
}
template <class D>
HWY_INLINE MaskF<D> MaskOfBits(D d, std::uint32_t bits) {
  const std::uint8_t bytes[8] = {static_cast<std::uint8_t>(bits), static_cast<std::uint8_t>(bits >> 8),
                                 static_cast<std::uint8_t>(bits >> 16), static_cast<std::uint8_t>(bits >> 24)};
  return hn::LoadMaskBits(d, bytes);
}

// The thread's LaneCounters where the variant counts; where it does not,
// every call compiles to nothing, so the variant without counters is the
// kernel as it was before they existed.
template <bool kOn>
class Tally {
 public:
  explicit Tally(LaneCounters* counters) : counters_(counters) {}
  template <class D>
  HWY_INLINE void Rays(D d, int depth, MaskF<D> active) const {
    if constexpr (kOn) counters_->raysPerDepth[static_cast<std::size_t>(depth)] += hn::CountTrue(d, active);
  }
  HWY_INLINE void Nodes(std::size_t visits, std::size_t slots, std::size_t active) const {
    if constexpr (kOn) {
      counters_->nodeVisits += visits;
      counters_->nodeLaneSlots += slots;
      counters_->nodeLanesActive += active;
    }
  }
  HWY_INLINE void Spheres(std::size_t tests, std::size_t slots, std::size_t active) const {
    if constexpr (kOn) {
      counters_->sphereTests += tests;
      counters_->sphereLaneSlots += slots;
      counters_->sphereLanesActive += active;
    }
  }
  template <class D>
  HWY_INLINE void Shading(D d, MaskF<D> hit) const {
    if constexpr (kOn) {
      counters_->shadeLaneSlots += hn::Lanes(d);
      counters_->shadeLanesActive += hn::CountTrue(d, hit);
    }
  }

 private:
  LaneCounters* counters_;
};

// ---- Intersection (docs/render-model.md section 3) ----------------------

#include "render/simd/sphere_query-inl.h"  // NearestHit()

// ---- Shading (docs/render-model.md section 4) -------------------------------------------

// x^e for x >= 0. Whole exponents (the scenes' 32) by repeated squaring,
// which stays within a few ulp of std::pow; others through exp(e log x).
template <class D>
HWY_INLINE VecF<D> Power(D d, VecF<D> x, float exponent) {
  constexpr float kMaxWholeExponent = 1 << 20;
  if (exponent == static_cast<float>(static_cast<int>(std::min(exponent, kMaxWholeExponent)))) {
    VecF<D> result = Splat(d, 1.0f);
    for (auto e = static_cast<unsigned>(exponent); e != 0; e >>= 1) {
      if (e & 1u) result = hn::Mul(result, x);
      x = hn::Mul(x, x);
    }
    return result;
  }
  if constexpr (kHalfLanes<D>) {
    // Highway's Exp and Log have no f16 form: lane by lane in float. No
    // committed scene gets here (their exponents are whole).
    HWY_ALIGN LaneT<D> lanes[hn::MaxLanes(D())];
    hn::Store(x, d, lanes);
    for (std::size_t i = 0; i < hn::Lanes(d); ++i) {
      const auto value = static_cast<float>(lanes[i]);
      lanes[i] = LaneValue<LaneT<D>>(value > 0.0f ? std::exp(exponent * std::log(value)) : 0.0f);
    }
    return hn::Load(d, lanes);
  } else {
    const VecF<D> positive = hn::Max(x, hn::Set(d, std::numeric_limits<float>::min()));
    return hn::IfThenElseZero(hn::Gt(x, hn::Zero(d)), hn::Exp(d, hn::Mul(hn::Set(d, exponent), hn::Log(d, positive))));
  }
}

// Phong with one directional light: ambient + diffuse + specular. Out of
// line for the same reason as NearestHit: once per packet width.
template <class D>
HWY_NOINLINE Vec3x<D> LocalColor(D d, const ShadingParams& shading, const RaycastHitX<D>& hit,
                                 const Vec3x<D>& direction) {
  const Vec3x<D> l = Broadcast(d, shading.toLight);
  const Vec3x<D> lightColor = Broadcast(d, shading.lightColor);
  const Vec3x<D>& n = hit.normal;
  const Vec3x<D> minusL = Sub(d, Zero3(d), l);
  const Vec3x<D> ambient = Mul(d, Broadcast(d, shading.ambientColor), hit.sphereColor);
  const Vec3x<D> diffuse = Mul(d, Scale(d, hn::Max(Dot(n, l), hn::Zero(d)), lightColor), hit.sphereColor);
  const Vec3x<D> rr = Sub(d, minusL, Scale(d, hn::Mul(Splat(d, 2.0f), Dot(minusL, n)), n));  // reflect(-l, n)
  const Vec3x<D> minusD = Sub(d, Zero3(d), direction);
  // Clamped to [0, 1] as in the scalar model (docs/render-model.md section 4).
  const VecF<D> cosine = hn::Min(hn::Max(Dot(rr, minusD), hn::Zero(d)), Splat(d, 1.0f));
  const VecF<D> highlight = Power(d, cosine, shading.shininess);
  return Add(d, Add(d, ambient, diffuse), Scale(d, hn::Mul(Splat(d, shading.specularStrength), highlight), lightColor));
}

// The bounce of docs/render-model.md section 5: offset origin, renormalised mirror direction.
template <class D>
HWY_INLINE RayX<D> ReflectedRay(D d, const RayX<D>& ray, const RaycastHitX<D>& hit) {
  const Vec3x<D>& dir = ray.direction;
  const Vec3x<D>& n = hit.normal;
  const Vec3x<D> origin = Add(d, hit.position, Scale(d, Splat(d, kEpsilon), n));
  return {origin, Normalize(d, Sub(d, dir, Scale(d, hn::Mul(Splat(d, 2.0f), Dot(dir, n)), n)))};
}

// ---- The two algorithms (docs/render-model.md section 5) --------------------------------

// A single-pass bounce, in the lanes that hit a sphere: its light joins the
// colour, its colour filters the throughput, and the ray reflects. The
// other lanes' throughput and ray become junk; they are not active again.
template <class D>
HWY_INLINE void ShadeBounce(D d, const ShadingParams& shading, const RaycastHitX<D>& hit, RayX<D>& ray, Vec3x<D>& color,
                            Vec3x<D>& throughput) {
  color = Select(d, Get(hit.hit), Add(d, color, Mul(d, throughput, LocalColor(d, shading, hit, ray.direction))), color);
  throughput = Mul(d, throughput, Scale(d, Splat(d, shading.reflectivity), hit.sphereColor));
  ray = ReflectedRay(d, ray, hit);
}

// Single-pass: colour and throughput accumulate on the way down. A lane
// that missed leaves `active`; since its ray would miss again, dropping it
// equals the scalar kernel, which keeps tracing it with zero throughput.
template <bool kBounceExit, bool kSphereExit, bool kDiscriminantExit, Search kSearch, bool kCount, class D>
HWY_INLINE Vec3x<D> TraceSinglePass(D d, const FrameParams& f, RayX<D> ray, MaskF<D> active, Tally<kCount> tally) {
  const Vec3x<D> background = Broadcast(d, f.shading.background);
  Vec3x<D> color = Zero3(d);
  Vec3x<D> throughput = Vec3Of(d, Splat(d, 1.0f), Splat(d, 1.0f), Splat(d, 1.0f));
  for (int depth = 0; depth < f.shading.maxDepth; ++depth) {
    tally.Rays(d, depth, active);
    const RaycastHitX<D> hit = NearestHit<kSphereExit, kDiscriminantExit, kSearch, kCount>(d, f, ray, active, tally);
    const MaskF<D> missed = hn::AndNot(Get(hit.hit), active);
    color = Select(d, missed, Add(d, color, Mul(d, throughput, background)), color);
    tally.Shading(d, Get(hit.hit));
    ShadeBounce(d, f.shading, hit, ray, color, throughput);
    active = Get(hit.hit);
    if constexpr (kBounceExit) {
      if (hn::AllFalse(d, active)) break;
    }
  }
  return color;
}

// One stored segment of the two-pass forward pass (the scalar PathSegment;
// the sphere colour travels in the hit record).
template <class D>
struct PathSegmentX {
  RayX<D> ray;
  RaycastHitX<D> hit;
};

// The forward pass' storage: per segment one ray, one hit and one sphere
// colour packet, stored vector by vector into the thread's scratch.
enum SegmentSlot : std::size_t {
  kOriginX,
  kOriginY,
  kOriginZ,
  kDirectionX,
  kDirectionY,
  kDirectionZ,
  kPositionX,
  kPositionY,
  kPositionZ,
  kNormalX,
  kNormalY,
  kNormalZ,
  kDistance,
  kColorR,
  kColorG,
  kColorB,
  kHitMask,
  kSegmentSlots
};
static_assert(kSegmentSlots == kSegmentVectors, "scratch sizing in packet_kernels.h must match");

template <class D>
class PathSegmentStore {
 public:
  // `base`: the thread's float scratch, holding packets of the lane type.
  PathSegmentStore(D d, float* base) : d_(d), base_(reinterpret_cast<LaneT<D>*>(base)), lanes_(hn::Lanes(d)) {}

  void put(int segment, const PathSegmentX<D>& s) const {
    put3(segment, kOriginX, s.ray.origin);
    put3(segment, kDirectionX, s.ray.direction);
    put3(segment, kPositionX, s.hit.position);
    put3(segment, kNormalX, s.hit.normal);
    hn::Store(Get(s.hit.distance), d_, at(segment, kDistance));
    put3(segment, kColorR, s.hit.sphereColor);
    hn::Store(hn::VecFromMask(d_, Get(s.hit.hit)), d_, at(segment, kHitMask));
  }
  [[nodiscard]] PathSegmentX<D> get(int segment) const {
    return {.ray = {.origin = get3(segment, kOriginX), .direction = get3(segment, kDirectionX)},
            .hit = {.hit = HoldMask(d_, hn::MaskFromVec(hn::Load(d_, at(segment, kHitMask)))),
                    .position = get3(segment, kPositionX),
                    .normal = get3(segment, kNormalX),
                    .distance = Hold(d_, hn::Load(d_, at(segment, kDistance))),
                    .sphereColor = get3(segment, kColorR)}};
  }

 private:
  LaneT<D>* at(int segment, std::size_t slot) const {
    return base_ + (static_cast<std::size_t>(segment) * kSegmentSlots + slot) * lanes_;
  }
  void put3(int segment, std::size_t first, const Vec3x<D>& v) const {
    hn::Store(Get(v.x), d_, at(segment, first));
    hn::Store(Get(v.y), d_, at(segment, first + 1));
    hn::Store(Get(v.z), d_, at(segment, first + 2));
  }
  Vec3x<D> get3(int segment, std::size_t first) const {
    return Vec3Of(d_, hn::Load(d_, at(segment, first)), hn::Load(d_, at(segment, first + 1)),
                  hn::Load(d_, at(segment, first + 2)));
  }

  D d_;
  LaneT<D>* base_;
  std::size_t lanes_;
};

// One step of the backward pass: the light gathered behind segment `s`
// (`acc`) seen through it, or the background where the lane missed.
template <class D>
HWY_INLINE Vec3x<D> FoldSegment(D d, const ShadingParams& shading, const Vec3x<D>& acc, const PathSegmentX<D>& s) {
  const Vec3x<D> lit = Add(d, Mul(d, Scale(d, Splat(d, shading.reflectivity), acc), s.hit.sphereColor),
                           LocalColor(d, shading, s.hit, s.ray.direction));
  return Select(d, Get(s.hit.hit), lit, Broadcast(d, shading.background));
}

// Two-pass (the thesis' original): the forward pass stores every segment,
// the backward pass walks them from the last one. A lane's segments after
// its miss are misses, as in the scalar kernel.
template <bool kBounceExit, bool kSphereExit, bool kDiscriminantExit, Search kSearch, bool kCount, class D>
HWY_INLINE Vec3x<D> TraceTwoPass(D d, const FrameParams& f, RayX<D> ray, MaskF<D> active, float* scratch,
                                 Tally<kCount> tally) {
  const PathSegmentStore<D> store(d, scratch);
  int count = 0;
  while (count < f.shading.maxDepth) {
    tally.Rays(d, count, active);
    const RaycastHitX<D> hit = NearestHit<kSphereExit, kDiscriminantExit, kSearch, kCount>(d, f, ray, active, tally);
    store.put(count++, {ray, hit});
    ray = ReflectedRay(d, ray, hit);
    active = Get(hit.hit);
    if constexpr (kBounceExit) {
      if (hn::AllFalse(d, active)) break;
    }
  }
  Vec3x<D> acc = Zero3(d);
  for (int i = count - 1; i >= 0; --i) {
    const PathSegmentX<D> segment = store.get(i);
    tally.Shading(d, Get(segment.hit.hit));
    acc = FoldSegment(d, f.shading, acc, segment);
  }
  return acc;
}

// ---- Pixel and span level -----------------------------------------------

// Primary rays of pixels x .. x+lanes-1 of the row at vertical coordinate v
// (docs/render-model.md section 2, the scalar primaryRay lane by lane).
// This and ToRgba8 run once per packet, not per bounce: out of line, they
// are compiled once per packet width instead of into each of the 32 span
// variants, which keeps the accel variant's cost in build time small.
template <class D>
HWY_NOINLINE RayX<D> PrimaryRayOfFloats(D d, const FrameParams& f, int x, float v) {
  const float w = static_cast<float>(f.extent.width);
  const float h = static_cast<float>(f.extent.height);
  const VecF<D> px = hn::Iota(d, static_cast<float>(x));
  const CameraFrame& c = f.camera;
  const VecF<D> u = hn::Mul(
      hn::Mul(hn::Sub(hn::Div(hn::Mul(Splat(d, 2.0f), hn::Add(px, Splat(d, 0.5f))), Splat(d, w)), Splat(d, 1.0f)),
              Splat(d, c.tanHalfFov)),
      Splat(d, w / h));
  const Vec3x<D> dir = Add(d, Add(d, Broadcast(d, c.forward), Scale(d, u, Broadcast(d, c.right))),
                           Scale(d, Splat(d, v), Broadcast(d, c.up)));
  return {Broadcast(d, c.position), Normalize(d, dir)};
}

// docs/render-model.md section 7: clamp, round(255 c), opaque; only the first n lanes land.
template <class D>
HWY_NOINLINE void ToRgba8OfFloats(D d, const Vec3x<D>& color, Rgba8* out, std::size_t n) {
  const hn::RebindToSigned<D> di;
  constexpr std::size_t kMax = hn::MaxLanes(D());
  HWY_ALIGN hn::TFromD<decltype(di)> channel[3][kMax];
  const auto quantize = [&](VecF<D> c) {
    const VecF<D> clamped = hn::Min(hn::Max(c, hn::Zero(d)), Splat(d, 1.0f));
    return hn::ConvertTo(di, hn::Add(hn::Mul(clamped, Splat(d, 255.0f)), Splat(d, 0.5f)));
  };
  hn::Store(quantize(Get(color.x)), di, channel[0]);
  hn::Store(quantize(Get(color.y)), di, channel[1]);
  hn::Store(quantize(Get(color.z)), di, channel[2]);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = Rgba8{static_cast<std::uint8_t>(channel[0][i]), static_cast<std::uint8_t>(channel[1][i]),
                   static_cast<std::uint8_t>(channel[2][i]), 255};
  }
}

// The f16 kernel's camera ray: its direction before normalisation is the
// scalar model's, in float, lane by lane, then rounded (a pixel coordinate
// past 2048 has no f16 value); the normalisation is in f16
// (docs/render-model.md section 10).
template <class D>
HWY_NOINLINE RayX<D> PrimaryRayOfHalves(D d, const FrameParams& f, int x, int y) {
  HWY_ALIGN LaneT<D> direction[3][hn::MaxLanes(D())];
  for (std::size_t i = 0; i < hn::Lanes(d); ++i) {
    const glm::vec3 dir = primaryRayDirection<float>(f.camera, f.extent, x + static_cast<int>(i), y);
    for (int k = 0; k < 3; ++k) direction[k][i] = LaneValue<LaneT<D>>(dir[k]);
  }
  const Vec3x<D> dir = Vec3Of(d, hn::Load(d, direction[0]), hn::Load(d, direction[1]), hn::Load(d, direction[2]));
  return {Broadcast(d, f.camera.position), Normalize(d, dir)};
}

// The f16 kernel's last step is the scalar model's, in float: an f16 sum of
// 255 c + 0.5 would round to its 1/8 steps above 128.
template <class D>
HWY_NOINLINE void ToRgba8OfHalves(D d, const Vec3x<D>& color, Rgba8* out, std::size_t n) {
  HWY_ALIGN LaneT<D> channel[3][hn::MaxLanes(D())];
  hn::Store(Get(color.x), d, channel[0]);
  hn::Store(Get(color.y), d, channel[1]);
  hn::Store(Get(color.z), d, channel[2]);
  for (std::size_t i = 0; i < n; ++i) {
    const auto widen = [&](int k) { return static_cast<float>(channel[k][i]); };
    out[i] = kernel::toRgba8(glm::vec3(widen(0), widen(1), widen(2)));
  }
}

// The camera rays of pixels x .. x+lanes-1 of row y; v is the row's vertical
// coordinate, which the float kernel takes computed once per row.
template <class D>
HWY_INLINE RayX<D> PrimaryRay(D d, const FrameParams& f, int x, int y, float v) {
  if constexpr (kHalfLanes<D>) {
    return PrimaryRayOfHalves(d, f, x, y);
  } else {
    return PrimaryRayOfFloats(d, f, x, v);
  }
}

template <class D>
HWY_INLINE void ToRgba8(D d, const Vec3x<D>& color, Rgba8* out, std::size_t n) {
  if constexpr (kHalfLanes<D>) {
    ToRgba8OfHalves(d, color, out, n);
  } else {
    ToRgba8OfFloats(d, color, out, n);
  }
}

template <class D, unsigned kVariant>
void RenderSpan(const FrameParams& f, int y, int x0, int x1, std::span<float> scratch, LaneCounters* counters) {
  constexpr KernelVariant kV = KernelVariant::fromIndex(kVariant);
  constexpr bool kTwoPass = kV.twoPass;
  constexpr bool kBounce = kV.bounceExit;
  constexpr bool kSphere = kV.sphereExit;
  constexpr bool kDiscriminant = kV.discriminantExit;
  constexpr Search kSearch = SearchOf(kV);
  const Tally<kV.counters> tally(counters);
  const D d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const float h = static_cast<float>(f.extent.height);
  const float v = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / h) * f.camera.tanHalfFov;
  Rgba8* row = f.pixels + static_cast<std::size_t>(y) * static_cast<std::size_t>(f.extent.width);
  for (int x = x0; x < x1; x += lanes) {
    const auto n = static_cast<std::size_t>(std::min(lanes, x1 - x));
    const MaskF<D> active = hn::FirstN(d, n);  // a partial packet at the row's end
    const RayX<D> ray = PrimaryRay(d, f, x, y, v);
    const Vec3x<D> color = [&] {
      if constexpr (kTwoPass) {
        return TraceTwoPass<kBounce, kSphere, kDiscriminant, kSearch>(d, f, ray, active, scratch.data(), tally);
      } else {
        return TraceSinglePass<kBounce, kSphere, kDiscriminant, kSearch>(d, f, ray, active, tally);
      }
    }();
    ToRgba8(d, color, row + x, n);
  }
}

// The variants kFirst, kFirst + 1, ... of one packet width; the others stay null.
template <unsigned kFirst, class D, unsigned... kOffsets>
LaneKernels MakeLaneKernels(D d, std::integer_sequence<unsigned, kOffsets...>) {
  LaneKernels kernels{static_cast<int>(hn::Lanes(d)), {}};
  ((kernels.variants[kFirst + kOffsets] = &RenderSpan<D, kFirst + kOffsets>), ...);
  return kernels;
}

// Half of the variants: those without counters, or those with them. Each
// half is compiled in a translation unit of its own (packet_kernels.cc,
// packet_kernels_counted.cc), so that the two compile side by side.
inline constexpr unsigned kHalfVariants = KernelVariant::kCount / 2;
static_assert(KernelVariant::fromIndex(kHalfVariants).counters && !KernelVariant::fromIndex(kHalfVariants - 1).counters,
              "the counting variants are the upper half");

// The f16 kernel is brute force only: the variants of the first half whose
// search bits (4-5) are zero.
inline constexpr unsigned kBruteForceVariants = 16;
static_assert(!KernelVariant::fromIndex(kBruteForceVariants - 1).bvh &&
                  KernelVariant::fromIndex(kBruteForceVariants).bvh,
              "the brute-force variants come first");

// Float lanes have every variant; f16 lanes the brute-force ones.
template <class T>
inline constexpr unsigned kVariantsOf = kHalfLane<T> ? kBruteForceVariants : kHalfVariants;

// The kernels for packets of exactly kLanes lanes of T, if this target has them.
template <unsigned kFirst, class T, std::size_t kLanes>
LaneKernels CappedKernels() {
  const hn::CappedTag<T, kLanes> d;
  if (hn::Lanes(d) != kLanes) return {};
  return MakeLaneKernels<kFirst>(d, std::make_integer_sequence<unsigned, kVariantsOf<T>>());
}

template <unsigned kFirst, class T, std::size_t... kIndex>
std::array<LaneKernels, sizeof...(kIndex)> AllCappedKernels(std::index_sequence<kIndex...>) {
  return {CappedKernels<kFirst, T, static_cast<std::size_t>(schema::kLaneWidths[kIndex])>()...};
}

// One lane type's kernels: the native width and each of the schema's lane widths.
template <unsigned kFirst, class T>
LaneSet LaneSetOf() {
  const NativeTag<T> d;
  LaneSet set;
  set.nativeLanes = static_cast<int>(hn::Lanes(d));
  set.native = MakeLaneKernels<kFirst>(d, std::make_integer_sequence<unsigned, kVariantsOf<T>>());
  set.capped = AllCappedKernels<kFirst, T>(std::make_index_sequence<schema::kLaneWidths.size()>());
  return set;
}

// What this target offers, for one half of the variants (without or with
// counters): float lanes, and f16 lanes where the target has native f16
// arithmetic. Returned by value through dispatch, so callers keep this
// target's function pointers and never dispatch per row.
template <unsigned kFirst>
TargetKernels HalfOfTargetKernels() {
  TargetKernels kernels;
  kernels.target = HWY_TARGET;
  kernels.f32 = LaneSetOf<kFirst, float>();
#if RT_SIMD_NATIVE_F16
  kernels.f16 = LaneSetOf<kFirst, hwy::float16_t>();
#endif
  return kernels;
}

}  // namespace rt::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
