// The spatial query of the SIMD kernel: per lane, the nearest sphere the
// ray hits (docs/render-model.md section 3). Brute force: every packet is
// tested against every sphere; with a BVH (--accel bvh) only the spheres
// whose boxes the ray reaches, the tree walked as --traversal says: by the
// packet, by each ray alone (wide_traversal-inl.h), or both in turn. This is
// the one place the packet kernels ask which sphere a ray meets; which way
// is a template parameter (Search), chosen once in prepare(). The names are the scalar kernel's
// (scalar/sphere_query.h) in Highway's case (docs/render-model.md section 9).
//
// A fragment, not a header: packet_kernel-inl.h includes it inside its
// per-target namespace, after the packet types, once per Highway target.

// One sphere against every lane (the scalar intersectSphere), and where it
// is hit nearer than the lane's best, it becomes the best: the scalar
// walks' `t < best` step folded in, since a lane cannot branch. A contract
// of its own, hence its own name (docs/render-model.md section 9). With kTieByIndex an exact tie goes to the
// lower index (needed where spheres come in tree order; brute force visits
// them in index order, where `<` alone settles ties the same way).
// kSphereExit / kDiscriminantExit are the thesis' two SIMD early exits.
// The sphere's values come in the lane type (LaneT<D>).
template <bool kSphereExit, bool kDiscriminantExit, bool kTieByIndex, class D>
HWY_INLINE void IntersectSphereIntoBest(D d, LaneT<D> centerX, LaneT<D> centerY, LaneT<D> centerZ,
                                        LaneT<D> radiusSquared, LaneT<D> index, const RayX<D>& ray, MaskF<D> active,
                                        VecF<D>& bestT, VecF<D>& bestIndex) {
  const VecF<D> eps = Splat(d, kEpsilon);
  const VecF<D> dx = Get(ray.direction.x);
  const VecF<D> dy = Get(ray.direction.y);
  const VecF<D> dz = Get(ray.direction.z);
  const VecF<D> ocx = hn::Sub(Get(ray.origin.x), hn::Set(d, centerX));
  const VecF<D> ocy = hn::Sub(Get(ray.origin.y), hn::Set(d, centerY));
  const VecF<D> ocz = hn::Sub(Get(ray.origin.z), hn::Set(d, centerZ));
  const VecF<D> b = hn::MulAdd(ocz, dz, hn::MulAdd(ocy, dy, hn::Mul(ocx, dx)));
  // f = oc - b d: centre to the point of closest approach; disc = r^2 - |f|^2.
  const VecF<D> fx = hn::NegMulAdd(b, dx, ocx);
  const VecF<D> fy = hn::NegMulAdd(b, dy, ocy);
  const VecF<D> fz = hn::NegMulAdd(b, dz, ocz);
  const VecF<D> disc = hn::Sub(hn::Set(d, radiusSquared), hn::MulAdd(fz, fz, hn::MulAdd(fy, fy, hn::Mul(fx, fx))));
  const MaskF<D> real = hn::And(active, hn::Ge(disc, hn::Zero(d)));
  if constexpr (kDiscriminantExit) {
    if (hn::AllFalse(d, real)) return;  // before the sqrt and all that follows
  }
  const VecF<D> h = hn::Sqrt(disc);  // NaN where disc < 0; those lanes are not `real`
  const VecF<D> minusB = hn::Sub(hn::Zero(d), b);
  const VecF<D> near = hn::Sub(minusB, h);
  const VecF<D> t = hn::IfThenElse(hn::Le(near, eps), hn::Add(minusB, h), near);
  const MaskF<D> hit = hn::And(real, hn::Gt(t, eps));
  if constexpr (kSphereExit) {
    if (hn::AllFalse(d, hit)) return;  // no lane hits: skip the bookkeeping
  }
  const VecF<D> lanesIndex = hn::Set(d, index);
  MaskF<D> better = hn::Lt(t, bestT);
  if constexpr (kTieByIndex) better = hn::Or(better, hn::And(hn::Eq(t, bestT), hn::Lt(lanesIndex, bestIndex)));
  const MaskF<D> closer = hn::And(hit, better);
  bestT = hn::IfThenElse(closer, t, bestT);
  bestIndex = hn::IfThenElse(closer, lanesIndex, bestIndex);
}

// The scene's arrays in the lane type: float, or the f16 copy.
template <class D>
HWY_INLINE const SphereData<LaneT<D>>& SpheresOf(const FrameParams& f) {
  if constexpr (kHalfLanes<D>) {
    return f.halfSpheres;
  } else {
    return f.spheres;
  }
}

// Sphere i of the scene's arrays (the index is exact in f16 up to
// kHalfPrecisionMaxSpheres, which prepare() enforces).
template <bool kSphereExit, bool kDiscriminantExit, bool kTieByIndex, class D>
HWY_INLINE void IntersectSphereIntoBest(D d, const RayX<D>& ray, const SphereData<LaneT<D>>& spheres, int i,
                                        MaskF<D> active, VecF<D>& bestT, VecF<D>& bestIndex) {
  IntersectSphereIntoBest<kSphereExit, kDiscriminantExit, kTieByIndex>(
      d, spheres.centerX[i], spheres.centerY[i], spheres.centerZ[i], spheres.radiusSquared[i],
      LaneValue<LaneT<D>>(static_cast<float>(i)), ray, active, bestT, bestIndex);
}

// base[i] per lane. Highway gathers 32- and 64-bit lanes only; 16-bit
// lanes are read one by one (once per bounce, not per sphere).
template <class D>
HWY_INLINE VecF<D> GatherLanes(D d, const LaneT<D>* base, hn::Vec<hn::RebindToSigned<D>> index) {
  if constexpr (!kHalfLanes<D>) {
    return hn::GatherIndex(d, base, index);
  } else {
    const hn::RebindToSigned<D> di;
    HWY_ALIGN hn::TFromD<decltype(di)> indices[hn::MaxLanes(D())];
    HWY_ALIGN LaneT<D> values[hn::MaxLanes(D())];
    hn::Store(index, di, indices);
    for (std::size_t lane = 0; lane < hn::Lanes(d); ++lane) values[lane] = base[indices[lane]];
    return hn::Load(d, values);
  }
}

template <class D>
HWY_INLINE Vec3x<D> Gather3(D d, const LaneT<D>* x, const LaneT<D>* y, const LaneT<D>* z,
                            hn::Vec<hn::RebindToSigned<D>> i) {
  return Vec3Of(d, GatherLanes(d, x, i), GatherLanes(d, y, i), GatherLanes(d, z, i));
}

// The hit records of the lanes' best spheres (index -1: a miss). Where the
// ray leaves the sphere (it started inside) the normal is turned to the
// side the ray sees (docs/render-model.md section 4).
template <class D>
HWY_INLINE RaycastHitX<D> HitRecord(D d, const SphereData<LaneT<D>>& spheres, const RayX<D>& ray, VecF<D> t,
                                    VecF<D> index) {
  const MaskF<D> hit = hn::Ge(index, hn::Zero(d));
  // Missed lanes read sphere 0 at distance 0: junk, but finite junk.
  const hn::RebindToSigned<D> di;
  const auto sphere = hn::ConvertTo(di, hn::Max(index, hn::Zero(d)));
  const VecF<D> distance = hn::IfThenElseZero(hit, t);
  const Vec3x<D> position = Add(d, ray.origin, Scale(d, distance, ray.direction));
  const Vec3x<D> center = Gather3(d, spheres.centerX, spheres.centerY, spheres.centerZ, sphere);
  const Vec3x<D> outward = Divide(d, Sub(d, position, center), GatherLanes(d, spheres.radius, sphere));
  const MaskF<D> leaving = hn::Gt(Dot(ray.direction, outward), hn::Zero(d));
  return {.hit = HoldMask(d, hit),
          .position = position,
          .normal = Select(d, leaving, Scale(d, Splat(d, -1.0f), outward), outward),
          .distance = Hold(d, distance),
          .sphereColor = Gather3(d, spheres.colorR, spheres.colorG, spheres.colorB, sphere)};
}

// Brute force: every sphere in index order. Lanes outside `active` (past
// the row's end, or already missed) report no hit.
template <bool kSphereExit, bool kDiscriminantExit, bool kCount, class D>
HWY_INLINE RaycastHitX<D> NearestHitOfAll(D d, const SphereData<LaneT<D>>& spheres, const RayX<D>& ray, MaskF<D> active,
                                          Tally<kCount> tally) {
  VecF<D> bestT = Splat(d, std::numeric_limits<float>::infinity());
  VecF<D> bestIndex = Splat(d, -1.0f);
  for (int i = 0; i < spheres.count; ++i) {
    IntersectSphereIntoBest<kSphereExit, kDiscriminantExit, false>(d, ray, spheres, i, active, bestT, bestIndex);
  }
  if constexpr (kCount) {
    const auto n = static_cast<std::size_t>(spheres.count);
    tally.Spheres(n, n * hn::Lanes(d), n * hn::CountTrue(d, active));
  }
  return HitRecord(d, spheres, ray, bestT, bestIndex);
}

// The lanes of `active` that may meet a sphere inside the box lo..hi,
// widened by `pad` (per lane: traversalPad() of its origin), nearer than
// their `best` (+ pad); `entry` receives where each lane enters the
// widened box. The scalar boxReachable per lane (docs/render-model.md
// section 9).
template <class D>
HWY_INLINE MaskF<D> BoxReachable(D d, const float lo[3], const float hi[3], const RayX<D>& ray, const Vec3x<D>& inverse,
                                 VecF<D> pad, VecF<D> best, MaskF<D> active, VecF<D>& entry) {
  const auto slab = [&](float l, float h, VecF<D> o, VecF<D> inv, VecF<D>& near, VecF<D>& far) {
    const VecF<D> t0 = hn::Mul(hn::Sub(hn::Sub(hn::Set(d, l), pad), o), inv);
    const VecF<D> t1 = hn::Mul(hn::Sub(hn::Add(hn::Set(d, h), pad), o), inv);
    near = hn::Min(t0, t1);
    far = hn::Max(t0, t1);
  };
  VecF<D> nx, fx, ny, fy, nz, fz;
  slab(lo[0], hi[0], Get(ray.origin.x), Get(inverse.x), nx, fx);
  slab(lo[1], hi[1], Get(ray.origin.y), Get(inverse.y), ny, fy);
  slab(lo[2], hi[2], Get(ray.origin.z), Get(inverse.z), nz, fz);
  entry = hn::Max(nx, hn::Max(ny, nz));
  const VecF<D> exit = hn::Min(fx, hn::Min(fy, fz));
  const MaskF<D> crosses = hn::And(hn::Le(entry, exit), hn::Ge(exit, hn::Sub(hn::Zero(d), pad)));
  return hn::And(active, hn::And(crosses, hn::Le(entry, hn::Add(best, pad))));
}

// 1 / d per lane, a zero component made a tiny one of its sign (no 0 * inf).
template <class D>
HWY_INLINE Vec3x<D> InverseDirection(D d, const Vec3x<D>& direction) {
  const VecF<D> tiny = hn::Set(d, 1e-30f);
  const auto safe = [&](VecF<D> c) { return hn::IfThenElse(hn::Lt(hn::Abs(c), tiny), hn::CopySign(tiny, c), c); };
  const VecF<D> one = hn::Set(d, 1.0f);
  return Vec3Of(d, hn::Div(one, safe(Get(direction.x))), hn::Div(one, safe(Get(direction.y))),
                hn::Div(one, safe(Get(direction.z))));
}

// traversalPad() (render/accel/bvh.h) per lane, in the tree's pad model.
template <class D>
HWY_INLINE VecF<D> TraversalPad(D d, const Bvh& bvh, const Vec3x<D>& origin) {
  const VecF<D> originMax = hn::Max(hn::Abs(Get(origin.x)), hn::Max(hn::Abs(Get(origin.y)), hn::Abs(Get(origin.z))));
  const VecF<D> scale = hn::Add(originMax, hn::Set(d, bvh.pad.coordinate));
  const VecF<D> scenePad = hn::Add(
      hn::Add(hn::Mul(hn::Set(d, float(RT_BVH_PAD_SCALE)), scale),
              hn::Mul(hn::Set(d, float(RT_BVH_PAD_TANGENT)), hn::Sqrt(hn::Mul(hn::Set(d, bvh.pad.radius), scale)))),
      hn::Set(d, float(RT_BVH_PAD_RADIUS) * bvh.pad.radius + float(RT_BVH_PAD_MIN)));
  return hn::Add(scenePad, hn::Mul(hn::Set(d, bvh.pad.originSlope), originMax));
}

// With a BVH: the packet walks the tree together, visiting a node while
// any active lane reaches its box, near child first by the summed direction
// of the active lanes (reflected lanes fan out: the first lane alone often
// picks the wrong side); each lane ends with the same nearest sphere as
// brute force.
template <bool kSphereExit, bool kDiscriminantExit, bool kCount, class D>
HWY_INLINE RaycastHitX<D> NearestHitInBvh(D d, const SphereArrays& spheres, const RayX<D>& ray, MaskF<D> active,
                                          Tally<kCount> tally) {
  const Bvh& bvh = *spheres.bvh;
  VecF<D> bestT = hn::Set(d, std::numeric_limits<float>::infinity());
  VecF<D> bestIndex = hn::Set(d, -1.0f);
  const Vec3x<D> inverse = InverseDirection(d, ray.direction);
  const VecF<D> pad = TraversalPad(d, bvh, ray.origin);
  const auto activeSum = [&](VecF<D> c) { return hn::GetLane(hn::SumOfLanes(d, hn::IfThenElseZero(active, c))); };
  const float direction[3] = {activeSum(Get(ray.direction.x)), activeSum(Get(ray.direction.y)),
                              activeSum(Get(ray.direction.z))};
  std::uint32_t stack[kBvhMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = bvh.nodes[stack[--top]];
    const float lo[3] = {node.lo.x, node.lo.y, node.lo.z};
    const float hi[3] = {node.hi.x, node.hi.y, node.hi.z};
    VecF<D> entry;  // unused here: the packet walk orders children by the lanes' summed direction
    const MaskF<D> reach = BoxReachable(d, lo, hi, ray, inverse, pad, bestT, active, entry);
    if constexpr (kCount) tally.Nodes(1, hn::Lanes(d), hn::CountTrue(d, reach));
    if (hn::AllFalse(d, reach)) continue;
    if (!node.leaf()) {
      const bool negative = direction[node.axis()] < 0.0f;
      stack[top++] = node.first + (negative ? 0u : 1u);  // far child
      stack[top++] = node.first + (negative ? 1u : 0u);  // near child, visited next
      continue;
    }
    if constexpr (kCount)
      tally.Spheres(node.count(), node.count() * hn::Lanes(d), node.count() * hn::CountTrue(d, reach));
    for (std::uint32_t k = node.first; k < node.first + node.count(); ++k) {
      IntersectSphereIntoBest<kSphereExit, kDiscriminantExit, true>(d, ray, spheres, static_cast<int>(bvh.order[k]),
                                                                    active, bestT, bestIndex);
    }
  }
  return HitRecord(d, spheres, ray, bestT, bestIndex);
}

#include "render/simd/wide_traversal-inl.h"  // NearestHitSingle(), NearestHitHybrid()

// How a variant finds the nearest sphere: brute force, or the BVH walked
// as --traversal says.
enum class Search { kAll, kPacket, kSingle, kHybrid };

constexpr Search SearchOf(KernelVariant v) {
  if (!v.bvh) return Search::kAll;
  switch (v.traversal) {
    case Traversal::packet: return Search::kPacket;
    case Traversal::single: return Search::kSingle;
    case Traversal::hybrid: return Search::kHybrid;
  }
  return Search::kPacket;
}

// The nearest hit per lane, lower index on a tie; kSearch is the compiled
// variant of --accel and --traversal. Out of line: the sphere loop is the
// bulk of the code, and this way it is compiled once per search, exit pair
// and counting, not once for each variant of the span kernel (the call
// costs nothing next to a loop over spheres). The single-ray walk does not
// use the thesis' packet exits: one copy serves every exit pair.
template <bool kSphereExit, bool kDiscriminantExit, Search kSearch, bool kCount, class D>
HWY_NOINLINE RaycastHitX<D> NearestHit(D d, const FrameParams& f, const RayX<D>& ray, MaskF<D> active,
                                       Tally<kCount> tally) {
  if constexpr (kSearch == Search::kAll) {
    return NearestHitOfAll<kSphereExit, kDiscriminantExit>(d, SpheresOf<D>(f), ray, active, tally);
  } else if constexpr (kSearch == Search::kPacket) {
    return NearestHitInBvh<kSphereExit, kDiscriminantExit>(d, f.spheres, ray, active, tally);
  } else if constexpr (kSearch == Search::kSingle) {
    return NearestHitSingle(d, f.spheres, ray, active, tally);
  } else {
    return NearestHitHybrid<kSphereExit, kDiscriminantExit>(d, f.spheres, ray, active, f.hybridThreshold, tally);
  }
}
