// The spatial query of the SIMD kernel: per lane, the nearest sphere the
// ray hits (docs/render-model.md section 3). Brute force: every packet is
// tested against every sphere. This is the one place the packet kernels ask
// the scene which sphere a ray meets; an acceleration structure replaces
// the loop in NearestSphere().
//
// A fragment, not a header: packet_kernel-inl.h includes it inside its
// per-target namespace, after the packet types, once per Highway target.

// Nearest sphere per lane over all spheres, lower index on a tie. Lanes
// outside `active` (past the row's end, or already missed) report no hit.
// kSphereExit / kDiscriminantExit are the thesis' two SIMD early exits.
template <bool kSphereExit, bool kDiscriminantExit, class D>
HWY_INLINE void NearestSphere(D d, const SphereArrays& s, const RayX<D>& ray, MaskF<D> active, VecF<D>& bestT,
                              VecF<D>& bestIndex) {
  const VecF<D> eps = hn::Set(d, kEpsilon);
  bestT = hn::Set(d, std::numeric_limits<float>::infinity());
  bestIndex = hn::Set(d, -1.0f);
  const Vec3x<D>& o = ray.origin;
  const Vec3x<D>& dir = ray.direction;
  for (int i = 0; i < s.count; ++i) {
    const VecF<D> ocx = o.x - hn::Set(d, s.centerX[i]);
    const VecF<D> ocy = o.y - hn::Set(d, s.centerY[i]);
    const VecF<D> ocz = o.z - hn::Set(d, s.centerZ[i]);
    const VecF<D> b = hn::MulAdd(ocz, dir.z, hn::MulAdd(ocy, dir.y, ocx * dir.x));
    // f = oc - b d: centre to the point of closest approach; disc = r^2 - |f|^2.
    const VecF<D> fx = hn::NegMulAdd(b, dir.x, ocx);
    const VecF<D> fy = hn::NegMulAdd(b, dir.y, ocy);
    const VecF<D> fz = hn::NegMulAdd(b, dir.z, ocz);
    const VecF<D> disc = hn::Set(d, s.radiusSquared[i]) - hn::MulAdd(fz, fz, hn::MulAdd(fy, fy, fx * fx));
    const MaskF<D> real = hn::And(active, disc >= hn::Zero(d));
    if constexpr (kDiscriminantExit) {
      if (hn::AllFalse(d, real)) continue;  // before the sqrt and all that follows
    }
    const VecF<D> h = hn::Sqrt(disc);  // NaN where disc < 0; those lanes are not `real`
    const VecF<D> minusB = hn::Zero(d) - b;
    const VecF<D> near = minusB - h;
    const VecF<D> t = hn::IfThenElse(near <= eps, minusB + h, near);
    const MaskF<D> hit = hn::And(real, t > eps);
    if constexpr (kSphereExit) {
      if (hn::AllFalse(d, hit)) continue;  // no lane hits: skip the bookkeeping
    }
    const MaskF<D> closer = hn::And(hit, t < bestT);
    bestT = hn::IfThenElse(closer, t, bestT);
    bestIndex = hn::IfThenElse(closer, hn::Set(d, static_cast<float>(i)), bestIndex);
  }
}
