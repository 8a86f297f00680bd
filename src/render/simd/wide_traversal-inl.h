// Single rays through the wide BVH (--traversal single) and packets that
// split into single rays once few of their lanes stay together (--traversal
// hybrid). Reflected rays of one packet fan out after a bounce, so a packet
// reaches most nodes with few lanes active: masked lanes doing no work.
// A single ray instead fills the vector with a node's child boxes, or a
// leaf's spheres. Both give each lane the same nearest sphere as brute
// force: the sphere test is the packet's lane for lane (IntersectSphereIntoBest,
// the same operations in the same order), the boxes are padded as the
// packet's (traversalPad), and ties go to the lower index.
//
// A fragment, not a header: sphere_query-inl.h includes it inside its
// per-target namespace, once per Highway target.

// The vector of a wide node's children (8 floats; two halves on 4-lane targets).
using WideTag = hn::CappedTag<float, kWideBvhWidth>;

// One ray as the single walk holds it: broadcast once per ray, and per axis
// the plane of a node's boxes it meets first (lo where it travels up the
// axis), so a box costs a subtraction and a multiplication per plane.
struct SingleRayX {
  // Written out rather than implicit: GCC compiles an implicit constructor
  // of a non-template struct without the target's attributes, so with
  // Highway 1.0 on NEON (whose target adds +crypto) it cannot inline the
  // vectors' always-inline constructors and the build fails.
  HWY_INLINE SingleRayX() {}
  HeldF<WideTag> origin[3];
  HeldF<WideTag> direction[3];
  HeldF<WideTag> inverse[3];
  // The origin moved by the pad away from the near (far) plane, times the
  // inverse direction: a plane at p is entered at p inverse - shift.
  HeldF<WideTag> nearShift[3];
  HeldF<WideTag> farShift[3];
  int nearPlane[3];
  int farPlane[3];
  float pad;
};

// Lane `lane` of a packet's ray, inverse direction and pad, as stored by StoreLanes.
struct PacketLanes {
  static constexpr std::size_t kMaxLanes = kMaxPacketLanes;
  HWY_ALIGN float origin[3][kMaxLanes];
  HWY_ALIGN float direction[3][kMaxLanes];
  HWY_ALIGN float inverse[3][kMaxLanes];
  HWY_ALIGN float pad[kMaxLanes];
};

template <class D>
HWY_INLINE void StoreLanes(D d, const RayX<D>& ray, const Vec3x<D>& inverse, VecF<D> pad, PacketLanes& out) {
  static_assert(hn::MaxLanes(D()) <= PacketLanes::kMaxLanes);
  const auto put = [&](const Vec3x<D>& v, float(*to)[PacketLanes::kMaxLanes]) {
    hn::Store(Get(v.x), d, to[0]);
    hn::Store(Get(v.y), d, to[1]);
    hn::Store(Get(v.z), d, to[2]);
  };
  put(ray.origin, out.origin);
  put(ray.direction, out.direction);
  put(inverse, out.inverse);
  hn::Store(pad, d, out.pad);
}

HWY_INLINE SingleRayX SingleRayOf(const PacketLanes& lanes, std::size_t lane) {
  const WideTag dw;
  SingleRayX r;
  r.pad = lanes.pad[lane];
  for (int a = 0; a < 3; ++a) {
    const float o = lanes.origin[a][lane];
    const float inv = lanes.inverse[a][lane];
    const bool up = !(inv < 0.0f);
    r.origin[a] = Hold(dw, hn::Set(dw, o));
    r.direction[a] = Hold(dw, hn::Set(dw, lanes.direction[a][lane]));
    r.inverse[a] = Hold(dw, hn::Set(dw, inv));
    // (lo - pad - o) inv = lo inv - (o + pad) inv up the axis; down it, hi + pad is met first.
    // The fused form rounds differently from the packet's (lo - pad - o) inv by
    // about 1e-7 of (|o| + |lo|) |inv|, far inside the pad's 1e-5 of that scale.
    r.nearShift[a] = Hold(dw, hn::Set(dw, (up ? o + r.pad : o - r.pad) * inv));
    r.farShift[a] = Hold(dw, hn::Set(dw, (up ? o - r.pad : o + r.pad) * inv));
    r.nearPlane[a] = up ? WideBvhNode::kLoX + a : WideBvhNode::kHiX + a;
    r.farPlane[a] = up ? WideBvhNode::kHiX + a : WideBvhNode::kLoX + a;
  }
  return r;
}

// The slots of `node` whose padded box the ray enters before leaving it and
// nearer than bestT + pad (the packet's BoxReachable, one ray against the
// node's boxes); `entry` receives the entry distance per slot.
HWY_INLINE std::uint32_t WideNodeHits(const WideBvhNode& node, const SingleRayX& r, float bestT, float* entry) {
  const WideTag dw;
  const std::size_t n = hn::Lanes(dw);
  const VecF<WideTag> lowest = hn::Set(dw, -r.pad);
  const VecF<WideTag> highest = hn::Set(dw, bestT + r.pad);
  std::uint32_t bits = 0;
  for (std::size_t c = 0; c < WideBvhNode::kWidth; c += n) {
    const auto plane = [&](int p, int a, const HeldF<WideTag>* shift) {
      return hn::MulSub(hn::Load(dw, node.bounds[static_cast<std::size_t>(p)].data() + c), Get(r.inverse[a]),
                        Get(shift[a]));
    };
    const VecF<WideTag> enter =
        hn::Max(hn::Max(plane(r.nearPlane[0], 0, r.nearShift), plane(r.nearPlane[1], 1, r.nearShift)),
                hn::Max(plane(r.nearPlane[2], 2, r.nearShift), lowest));
    const VecF<WideTag> leave =
        hn::Min(hn::Min(plane(r.farPlane[0], 0, r.farShift), plane(r.farPlane[1], 1, r.farShift)),
                hn::Min(plane(r.farPlane[2], 2, r.farShift), highest));
    hn::Store(enter, dw, entry + c);
    bits |= LaneBits(dw, hn::Le(enter, leave)) << c;
  }
  return bits;
}

// The leaf's spheres against one ray, a vector of them at a time; the
// nearest hit, lower index on a tie, becomes the best.
template <bool kCount>
HWY_INLINE void LeafNearest(const WideBvh& w, WideChild leaf, const SingleRayX& r, float& bestT,
                            std::int32_t& bestIndex, Tally<kCount> tally) {
  const WideTag dw;
  const std::size_t n = hn::Lanes(dw);
  const VecF<WideTag> eps = hn::Set(dw, kEpsilon);
  const LeafBlock& block = w.leaves[leaf.block()];
  const std::size_t count = leaf.count();
  const VecF<WideTag> ox = Get(r.origin[0]), oy = Get(r.origin[1]), oz = Get(r.origin[2]);
  const VecF<WideTag> dx = Get(r.direction[0]), dy = Get(r.direction[1]), dz = Get(r.direction[2]);
  for (std::size_t c = 0; c < count; c += n) {
    if constexpr (kCount) tally.Spheres(1, n, std::min(n, count - c));
    // intersectSphere, lane for lane as IntersectSphereIntoBest computes it with the spheres' values broadcast.
    const VecF<WideTag> ocx = hn::Sub(ox, hn::Load(dw, block.centerX.data() + c));
    const VecF<WideTag> ocy = hn::Sub(oy, hn::Load(dw, block.centerY.data() + c));
    const VecF<WideTag> ocz = hn::Sub(oz, hn::Load(dw, block.centerZ.data() + c));
    const VecF<WideTag> b = hn::MulAdd(ocz, dz, hn::MulAdd(ocy, dy, hn::Mul(ocx, dx)));
    const VecF<WideTag> fx = hn::NegMulAdd(b, dx, ocx);
    const VecF<WideTag> fy = hn::NegMulAdd(b, dy, ocy);
    const VecF<WideTag> fz = hn::NegMulAdd(b, dz, ocz);
    const VecF<WideTag> disc =
        hn::Sub(hn::Load(dw, block.radiusSquared.data() + c), hn::MulAdd(fz, fz, hn::MulAdd(fy, fy, hn::Mul(fx, fx))));
    const MaskF<WideTag> real = hn::Ge(disc, hn::Zero(dw));  // never in unused slots (radius squared -1)
    if (hn::AllFalse(dw, real)) continue;
    const VecF<WideTag> h = hn::Sqrt(disc);
    const VecF<WideTag> minusB = hn::Sub(hn::Zero(dw), b);
    const VecF<WideTag> near = hn::Sub(minusB, h);
    const VecF<WideTag> t = hn::IfThenElse(hn::Le(near, eps), hn::Add(minusB, h), near);
    std::uint32_t hits = LaneBits(dw, hn::And(real, hn::Gt(t, eps)));
    if (hits == 0) continue;
    HWY_ALIGN float ts[WideBvhNode::kWidth];
    hn::Store(t, dw, ts);
    for (; hits != 0; hits &= hits - 1) {
      const auto j = static_cast<std::size_t>(std::countr_zero(hits));
      const std::int32_t index = w.index[leaf.block() * std::size_t{kWideBvhWidth} + c + j];
      if (ts[j] < bestT || (ts[j] == bestT && index < bestIndex)) {
        bestT = ts[j];
        bestIndex = index;
      }
    }
  }
}

// Where a walk goes next: a wide node or a leaf, and the
// distance at which the ray (the nearest of the packet's lanes) enters its box.
struct WideEntry {
  WideChild child;
  float entry;
};

// Levels of the wide tree at most: never more than the binary tree's, and
// a pile of coincident spheres adds a node of leaves per factor of 8.
inline constexpr int kWideMaxDepth = kBvhMaxDepth + 12;
// At most kWidth - 1 siblings wait per level, one level per node on the path.
inline constexpr int kWideStackSize = (kWideBvhWidth - 1) * (kWideMaxDepth + 1) + 1;

// Starts loading a node's boxes (or a leaf's spheres) into the cache.
HWY_INLINE void Prefetch(const WideBvh& w, WideChild child) {
  const char* at = child.leaf() ? reinterpret_cast<const char*>(&w.leaves[child.block()])
                                : reinterpret_cast<const char*>(&w.nodes[child.node()]);
  hwy::Prefetch(at);
  hwy::Prefetch(at + 64);
  if (!child.leaf()) {
    hwy::Prefetch(at + 128);
    hwy::Prefetch(at + 192);
  }
}

// One ray from `start` down: a node's hit children are ordered by entry
// distance with the nearest visited next (one hit: nothing is pushed), and
// a waiting child is dropped once the ray's best hit is nearer than its box.
template <bool kCount>
HWY_NOINLINE void WalkSingle(const WideBvh& w, WideEntry start, const SingleRayX& r, float& bestT,
                             std::int32_t& bestIndex, Tally<kCount> tally) {
  WideEntry stack[kWideStackSize];
  int top = 0;
  WideEntry current = start;
  for (;;) {
    if (!current.child.leaf()) {
      const WideBvhNode& node = w.nodes[current.child.node()];
      HWY_ALIGN float entry[WideBvhNode::kWidth];
      std::uint32_t hits = WideNodeHits(node, r, bestT, entry);
      if constexpr (kCount) tally.Nodes(1, WideBvhNode::kWidth, node.childCount);
      if (hits != 0) {
        if ((hits & (hits - 1)) == 0) {
          const auto j = static_cast<std::size_t>(std::countr_zero(hits));
          current = {node.child[j], entry[j]};
          continue;
        }
        // Onto the stack in order, the farthest deepest; the nearest comes straight off again.
        WideEntry* const first = stack + top;
        for (; hits != 0; hits &= hits - 1) {
          const auto j = static_cast<std::size_t>(std::countr_zero(hits));
          const WideEntry e{node.child[j], entry[j]};
          Prefetch(w, e.child);  // waiting on the stack, it arrives meanwhile
          WideEntry* k = stack + top++;
          for (; k > first && (k - 1)->entry < e.entry; --k) *k = *(k - 1);
          *k = e;
        }
        current = stack[--top];
        continue;
      }
    } else {
      LeafNearest(w, current.child, r, bestT, bestIndex, tally);
    }
    do {
      if (top == 0) return;
      current = stack[--top];
    } while (current.entry > bestT + r.pad);
  }
}

// Each active lane alone through the wide BVH (--traversal single).
template <bool kCount, class D>
HWY_INLINE RaycastHitX<D> NearestHitSingle(D d, const SphereArrays& s, const RayX<D>& ray, MaskF<D> active,
                                           Tally<kCount> tally) {
  PacketLanes lanes;
  StoreLanes(d, ray, InverseDirection(d, ray.direction), TraversalPad(d, *s.bvh, ray.origin), lanes);
  const hn::RebindToSigned<D> di;
  HWY_ALIGN float bestT[PacketLanes::kMaxLanes];
  HWY_ALIGN std::int32_t bestIndex[PacketLanes::kMaxLanes];
  hn::Store(hn::Set(d, std::numeric_limits<float>::infinity()), d, bestT);
  hn::Store(hn::Set(di, -1), di, bestIndex);
  for (std::uint32_t bits = LaneBits(d, active); bits != 0; bits &= bits - 1) {
    const auto lane = static_cast<std::size_t>(std::countr_zero(bits));
    WalkSingle(*s.wide, WideEntry{WideChild::inner(0), 0.0f}, SingleRayOf(lanes, lane), bestT[lane], bestIndex[lane],
               tally);
  }
  return HitRecord(d, s, ray, hn::Load(d, bestT), hn::ConvertTo(d, hn::Load(di, bestIndex)));
}

// A box the hybrid walk's packet has yet to enter: where, and the lanes
// that reached it.
struct PacketEntry {
  WideEntry to;
  std::uint32_t lanes;
};

// Few lanes left: each goes on alone from `e` (as --traversal single), and
// its best hit comes back into the packet's.
template <bool kCount, class D>
HWY_INLINE void FinishLanesAlone(D d, const WideBvh& w, const PacketEntry& e, const PacketLanes& lanes, VecF<D>& bestT,
                                 VecF<D>& bestIndex, Tally<kCount> tally) {
  HWY_ALIGN float t[PacketLanes::kMaxLanes];
  HWY_ALIGN float index[PacketLanes::kMaxLanes];
  hn::Store(bestT, d, t);
  hn::Store(bestIndex, d, index);
  for (std::uint32_t bits = e.lanes; bits != 0; bits &= bits - 1) {
    const auto lane = static_cast<std::size_t>(std::countr_zero(bits));
    auto laneIndex = static_cast<std::int32_t>(index[lane]);
    WalkSingle(w, e.to, SingleRayOf(lanes, lane), t[lane], laneIndex, tally);
    index[lane] = static_cast<float>(laneIndex);
  }
  bestT = hn::Load(d, t);
  bestIndex = hn::Load(d, index);
}

// A leaf's spheres against the lanes that reached it, in index order.
template <bool kSphereExit, bool kDiscriminantExit, bool kCount, class D>
HWY_INLINE void PacketLeafNearest(D d, const WideBvh& w, const PacketEntry& e, const RayX<D>& ray, MaskF<D> reaching,
                                  VecF<D>& bestT, VecF<D>& bestIndex, Tally<kCount> tally) {
  const LeafBlock& block = w.leaves[e.to.child.block()];
  const std::uint32_t count = e.to.child.count();
  if constexpr (kCount) tally.Spheres(count, count * hn::Lanes(d), count * std::popcount(e.lanes));
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::int32_t index = w.index[e.to.child.block() * std::size_t{kWideBvhWidth} + k];
    IntersectSphereIntoBest<kSphereExit, kDiscriminantExit, true>(
        d, block.centerX[k], block.centerY[k], block.centerZ[k], block.radiusSquared[k], static_cast<float>(index), ray,
        reaching, bestT, bestIndex);
  }
}

// The node's children that some lane reaches nearer than its best hit +
// pad, pushed farthest first (the nearest comes off next). Returns the new top.
template <bool kCount, class D>
HWY_INLINE int PushReachedChildren(D d, const WideBvhNode& node, const RayX<D>& ray, const Vec3x<D>& inverse,
                                   VecF<D> pad, VecF<D> bestT, MaskF<D> reaching, PacketEntry* stack, int top,
                                   Tally<kCount> tally) {
  PacketEntry near[WideBvhNode::kWidth];
  int n = 0;
  for (std::size_t j = 0; j < node.childCount; ++j) {
    const float lo[3] = {node.bounds[WideBvhNode::kLoX][j], node.bounds[WideBvhNode::kLoY][j],
                         node.bounds[WideBvhNode::kLoZ][j]};
    const float hi[3] = {node.bounds[WideBvhNode::kHiX][j], node.bounds[WideBvhNode::kHiY][j],
                         node.bounds[WideBvhNode::kHiZ][j]};
    VecF<D> entry;
    const MaskF<D> reach = BoxReachable(d, lo, hi, ray, inverse, pad, bestT, reaching, entry);
    if constexpr (kCount) tally.Nodes(1, hn::Lanes(d), hn::CountTrue(d, reach));
    if (hn::AllFalse(d, reach)) continue;
    const float nearest = hn::GetLane(
        hn::MinOfLanes(d, hn::IfThenElse(reach, entry, hn::Set(d, std::numeric_limits<float>::infinity()))));
    PacketEntry p{{node.child[j], nearest}, LaneBits(d, reach)};
    int k = n++;
    for (; k > 0 && near[k - 1].to.entry < p.to.entry; --k) near[k] = near[k - 1];  // farthest first
    near[k] = p;
  }
  for (int k = 0; k < n; ++k) stack[top++] = near[k];
  return top;
}

// Packets through the wide BVH, one box of a node at a time, while more
// than `threshold` lanes reach it; below, each of those lanes goes on alone
// from that box (--traversal hybrid).
template <bool kSphereExit, bool kDiscriminantExit, bool kCount, class D>
HWY_INLINE RaycastHitX<D> NearestHitHybrid(D d, const SphereArrays& s, const RayX<D>& ray, MaskF<D> active,
                                           int threshold, Tally<kCount> tally) {
  const WideBvh& w = *s.wide;
  VecF<D> bestT = hn::Set(d, std::numeric_limits<float>::infinity());
  VecF<D> bestIndex = hn::Set(d, -1.0f);
  const Vec3x<D> inverse = InverseDirection(d, ray.direction);
  const VecF<D> pad = TraversalPad(d, *s.bvh, ray.origin);
  PacketLanes lanes;
  StoreLanes(d, ray, inverse, pad, lanes);
  PacketEntry stack[WideBvhNode::kWidth * (kWideMaxDepth + 1) + 1];
  int top = 0;
  stack[top++] = {{WideChild::inner(0), 0.0f}, LaneBits(d, active)};
  while (top > 0) {
    const PacketEntry e = stack[--top];
    if (std::popcount(e.lanes) <= threshold) {
      FinishLanesAlone(d, w, e, lanes, bestT, bestIndex, tally);
    } else if (e.to.child.leaf()) {
      PacketLeafNearest<kSphereExit, kDiscriminantExit>(d, w, e, ray, MaskOfBits(d, e.lanes), bestT, bestIndex, tally);
    } else {
      top = PushReachedChildren(d, w.nodes[e.to.child.node()], ray, inverse, pad, bestT, MaskOfBits(d, e.lanes), stack,
                                top, tally);
    }
  }
  return HitRecord(d, s, ray, bestT, bestIndex);
}
