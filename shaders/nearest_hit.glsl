// The nearest-hit query of docs/render-model.md section 3 for the GPU
// renderer, by brute force or by one of the two BVHs (--gpu-bvh), and the
// --counters tallies of each search: included by raytrace.comp after
// render_model.glsl. Every way gives the nearest hit of brute force, ties to
// the lower index (docs/render-model.md section 3, "How the GPU renderer
// walks the BVH").

// Counters (--counters; compiled out without) ================================================
// Each invocation tallies its own work; the subgroup's lane slots are
// tallied once per search by one invocation (the subgroup runs a loop as
// often as its busiest invocation). flushCounters() adds the tallies to the
// counter buffer once per invocation, subgroup-reduced.
uint searchNodes;    // of the search under way
uint searchSpheres;
uint tallyRays[MAX_DEPTH];
uint tallyNodeVisits = 0u;
uint tallyNodeLaneSlots = 0u;
uint tallySphereTests = 0u;
uint tallySphereLaneSlots = 0u;
uint tallyShadeLaneSlots = 0u;
uint tallyShadeLanesActive = 0u;

void beginCounting() {
  if (!COUNTERS) return;
  for (int d = 0; d < MAX_DEPTH; ++d) tallyRays[d] = 0u;
}



// One search at bounce `depth` has ended; `hit`: the ray found a sphere and is shaded.
void endSearch(int depth, bool hit) {
  if (!COUNTERS) return;
  tallyRays[depth] += 1u;
  tallyNodeVisits += searchNodes;
  tallySphereTests += searchSpheres;
  if (hit) tallyShadeLanesActive += 1u;
  uint busiestNodes = subgroupMax(searchNodes);
  uint busiestSpheres = subgroupMax(searchSpheres);
  if (subgroupElect()) {
    tallyNodeLaneSlots += busiestNodes * gl_SubgroupSize;
    tallySphereLaneSlots += busiestSpheres * gl_SubgroupSize;
    tallyShadeLaneSlots += gl_SubgroupSize;
  }
}

// Adds the subgroup's sum of `value` to 64-bit counter `slot` of this
// workgroup's copy. The sum is taken in 16-bit halves so that it cannot
// overflow 32 bits; the low word's carry goes into the high word.
void addToCounter(uint slot, uint value) {
  uint lowSum = subgroupAdd(value & 0xffffu);
  uint highSum = subgroupAdd(value >> 16);
  if (!subgroupElect() || (lowSum | highSum) == 0u) return;
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint at = ((group % uint(RT_COUNTER_COPIES)) * uint(RT_COUNTER_SLOTS) + slot) * 2u;
  uint low = (highSum << 16) + lowSum;
  uint high = (highSum >> 16) + (low < lowSum ? 1u : 0u);
  uint before = atomicAdd(counterWords[at], low);
  high += (before + low < before) ? 1u : 0u;
  if (high != 0u) atomicAdd(counterWords[at + 1u], high);
}

// Once per invocation, where its subgroup has reconverged.
void flushCounters() {
  if (!COUNTERS) return;
  for (int d = 0; d < MAX_DEPTH; ++d) addToCounter(uint(d), tallyRays[d]);
  addToCounter(RT_COUNTER_NODE_VISITS, tallyNodeVisits);
  addToCounter(RT_COUNTER_NODE_LANE_SLOTS, tallyNodeLaneSlots);
  addToCounter(RT_COUNTER_SPHERE_TESTS, tallySphereTests);
  addToCounter(RT_COUNTER_SPHERE_LANE_SLOTS, tallySphereLaneSlots);
  addToCounter(RT_COUNTER_SHADE_LANE_SLOTS, tallyShadeLaneSlots);
  addToCounter(RT_COUNTER_SHADE_LANES_ACTIVE, tallyShadeLanesActive);
}

// The best hit of the search under way, shared by the functions of the
// walks: its distance and sphere index.
float searchBest;
int searchBestIndex;

// A search starts with no hit and nothing counted: each of the searches
// below begins its own, so that each is the nearest hit of its ray alone,
// as its CPU twin is (docs/render-model.md section 9).
void beginSearch() {
  searchBest = 1.0 / 0.0;  // +infinity
  searchBestIndex = -1;
  searchNodes = 0u;
  searchSpheres = 0u;
}

// Brute force ================================================================================
// Brute force: the nearest hit over all spheres; on an exact tie the lower index wins.
RaycastHit nearestHitOfAll(Ray ray) {
  beginSearch();
  float best = 1.0 / 0.0;  // +infinity
  int bestIndex = -1;
  for (uint i = 0u; i < pc.sphereCount; ++i) {
    float t = toFloat(intersectSphere(ray, toReal4(spheres[i].positionRadius)));
    if (COUNTERS) ++searchSpheres;
    if (t > EPS && t < best) {
      best = t;
      bestIndex = int(i);
    }
  }
  return hitRecord(ray, toReal(best), bestIndex);
}


// The binary BVH (--gpu-bvh binary) ==========================================================

// rt::traversalPad (src/render/accel/bvh.h) for this ray's origin: how far
// a box is widened, in space and along the ray, so that no sphere the float
// test reports a hit on is culled with its box.
float traversalPad(vec3 origin) {
  vec3 a = abs(origin);
  float originMax = max(max(a.x, a.y), a.z);
  float scale = originMax + BVH_PAD_COORDINATE;
  float scenePad = float(RT_BVH_PAD_SCALE) * scale + float(RT_BVH_PAD_TANGENT) * sqrt(BVH_PAD_RADIUS * scale) +
                   float(RT_BVH_PAD_RADIUS) * BVH_PAD_RADIUS + float(RT_BVH_PAD_MIN);
  return scenePad + BVH_PAD_ORIGIN_SLOPE * originMax;
}

// 1 / direction, with a zero component made tiny (sign kept, -0 included),
// so that the slab test never computes 0 * infinity, and Vulkan's division
// stays inside the range where its precision is defined.
vec3 inverseDirection(vec3 direction) {
  const float tiny = 1e-30;
  uvec3 signs = floatBitsToUint(direction) & 0x80000000u;
  vec3 signedTiny = uintBitsToFloat(signs | floatBitsToUint(tiny));
  return 1.0 / mix(direction, signedTiny, lessThan(abs(direction), vec3(tiny)));
}

// Whether the ray may meet a sphere inside the box lo..hi nearer than
// `best` (+ pad); and the distance at which it enters the box. The CPU
// kernels' boxReachable, but on a box the upload widened already, by the
// pad of every ray the scene traces (rt::sceneTraversalPad), which is at
// least this ray's `pad`: widening it here, ray by ray, took 12 of a
// visit's additions (docs/experiments/gpu-traversal.md). Hence its own name
// (docs/render-model.md section 9).
bool prewidenedBoxReachable(vec3 lo, vec3 hi, Ray ray, vec3 inverse, float pad, float best, out float entry) {
  vec3 t0 = (lo - toFloat3(ray.origin)) * inverse;
  vec3 t1 = (hi - toFloat3(ray.origin)) * inverse;
  vec3 near = min(t0, t1);
  vec3 far = max(t0, t1);
  entry = max(max(near.x, near.y), near.z);
  float leave = min(min(far.x, far.y), far.z);
  return entry <= leave && leave >= -pad && entry <= best + pad;
}

// The scene index of leaf slot k of the BVH walked.
int leafSphereIndex(uint k) { return WIDE_BVH ? wideIndex[k] : int(bvhOrder[k]); }

// The sphere of leaf slot k against the best hit so far. The same
// intersectSphere gives each sphere the same t as brute force; an exact
// tie goes to the lower index, so the visit order cannot change the hit.
void testLeafSphere(Ray ray, uint k) {
  float t = toFloat(intersectSphere(ray, toReal4(leafSpheres[k])));
  if (t > EPS && t <= searchBest) {
    int index = leafSphereIndex(k);
    if (t < searchBest || index < searchBestIndex) {
      searchBest = t;
      searchBestIndex = index;
    }
  }
}

// A leaf: its `count` spheres from slot `first` in leaf order. A leaf of
// one sphere (every leaf of the binary walk's tree but where spheres
// coincide) is tested without the loop, which cost the H100 3 to 4 % of a
// frame from 10,000 spheres up (docs/experiments/gpu-traversal.md).
void testLeaf(Ray ray, uint first, uint count) {
  if (COUNTERS) searchSpheres += count;
  if (count == 1u) {
    testLeafSphere(ray, first);
    return;
  }
  for (uint k = first; k < first + count; ++k) testLeafSphere(ray, k);
}

// One child of a binary node: where it is reachable and a leaf, its spheres
// are tested at once (and it is reachable no more).
bool leafTestedOrReachable(bool reach, uint child, uint count, Ray ray) {
  if (!reach || count == 0u) return reach;
  testLeaf(ray, child, count);
  return false;
}

// With the binary BVH: the same nearest hit as brute force. A visit tests
// an inner node's two children's boxes (stored in the node, Aila and
// Laine's layout), tests the leaves among them at once, goes on to the
// nearer inner child reached and pushes the other with its entry distance;
// a pop skips an entry the ray can no longer reach nearer than its best hit
// (+ pad). One push per level: the tree's depth + 1 entries suffice
// (BVH_STACK_SIZE). An entry is the node and its entry distance's bits
// side by side, so that a push or a pop is one 8-byte access of the
// invocation's local memory rather than two of 4 bytes.
RaycastHit nearestHitInBvh(Ray ray) {
  beginSearch();
  vec3 inverse = inverseDirection(toFloat3(ray.direction));
  float pad = traversalPad(toFloat3(ray.origin));
  uvec2 stack[BVH_STACK_SIZE];  // node, floatBitsToUint(entry)
  int top = 0;
  uint node = 0u;  // the root
  while (true) {
    if (COUNTERS) ++searchNodes;
    uvec4 lo0 = bvhNodes[node * 4u], hi0 = bvhNodes[node * 4u + 1u];
    uvec4 lo1 = bvhNodes[node * 4u + 2u], hi1 = bvhNodes[node * 4u + 3u];
    float entry0, entry1;
    bool reach0 =
        prewidenedBoxReachable(uintBitsToFloat(lo0.xyz), uintBitsToFloat(hi0.xyz), ray, inverse, pad, searchBest, entry0);
    bool reach1 =
        prewidenedBoxReachable(uintBitsToFloat(lo1.xyz), uintBitsToFloat(hi1.xyz), ray, inverse, pad, searchBest, entry1);
    reach0 = leafTestedOrReachable(reach0, lo0.w, hi0.w, ray);
    reach1 = leafTestedOrReachable(reach1, lo1.w, hi1.w, ray);
    if (reach0 && reach1) {
      bool nearFirst = entry0 <= entry1;
      stack[top] = uvec2(nearFirst ? lo1.w : lo0.w, floatBitsToUint(nearFirst ? entry1 : entry0));
      ++top;
      node = nearFirst ? lo0.w : lo1.w;
      continue;
    }
    if (reach0 || reach1) {
      node = reach0 ? lo0.w : lo1.w;
      continue;
    }
    bool popped = false;
    while (top > 0 && !popped) {
      --top;
      popped = uintBitsToFloat(stack[top].y) <= searchBest + pad;
      node = stack[top].x;
    }
    if (!popped) break;
  }
  return hitRecord(ray, toReal(searchBest), searchBestIndex);
}

// The wide BVH (--gpu-bvh wide) ==============================================================
// rt::WideBvh (src/render/accel/wide_bvh.h) as the single traversal of the
// SIMD kernel walks it: a 256-byte node holds the boxes of up to eight
// children by plane (lo x, y, z, hi x, y, z; 8 floats each), then their
// child words (rt::WideChild), then the child count. Read as 16 uvec4s
// (the words come through untouched; the bounds are reinterpreted). A
// leaf's spheres are the leaf slots of its block (8 per block) in leafSpheres.
const uint WIDE_NODE_VEC4S = 16u;
const uint WIDE_CHILD_WORDS = 12u;  // the vec4s holding the child words
const uint WIDE_CHILD_COUNT = 14u;  // the vec4 whose x holds the child count
const uint WIDE_LEAF_BIT = 0x80000000u;
const uint WIDE_BLOCK_MASK = 0x0fffffffu;
const uint WIDE_WIDTH = 8u;

// The stack of children still to visit with the distance at which the ray
// enters each, kept outside the functions so that they share it without
// copying it.
uint wideStackChild[WIDE_STACK_SIZE];
float wideStackEntry[WIDE_STACK_SIZE];
int wideStackTop;

// Pushes a child the ray reaches. Unsorted: inserting it among the ones the
// same node pushed, farther ones deeper, kept the stack in local memory
// busier and measured 15 % slower on the H100 (docs/experiments/gpu-traversal.md).
void pushWideChild(uint child, float entry) {
  wideStackChild[wideStackTop] = child;
  wideStackEntry[wideStackTop] = entry;
  ++wideStackTop;
}

// The slab test of four children's boxes (one vec4 per plane), widened by
// `pad` as the CPU kernels' boxReachable() widens a box: which of them the
// ray may meet nearer than the best hit + pad, and where it enters each.
bvec4 wideBoxesReachable(uint base, uint upper, Ray ray, vec3 inverse, float pad, out vec4 entry) {
  vec4 t0x = (uintBitsToFloat(wideNodes[base + 0u + upper]) - pad - toFloat(ray.origin.x)) * inverse.x;
  vec4 t0y = (uintBitsToFloat(wideNodes[base + 2u + upper]) - pad - toFloat(ray.origin.y)) * inverse.y;
  vec4 t0z = (uintBitsToFloat(wideNodes[base + 4u + upper]) - pad - toFloat(ray.origin.z)) * inverse.z;
  vec4 t1x = (uintBitsToFloat(wideNodes[base + 6u + upper]) + pad - toFloat(ray.origin.x)) * inverse.x;
  vec4 t1y = (uintBitsToFloat(wideNodes[base + 8u + upper]) + pad - toFloat(ray.origin.y)) * inverse.y;
  vec4 t1z = (uintBitsToFloat(wideNodes[base + 10u + upper]) + pad - toFloat(ray.origin.z)) * inverse.z;
  entry = max(max(min(t0x, t1x), min(t0y, t1y)), min(t0z, t1z));
  vec4 leave = min(min(max(t0x, t1x), max(t0y, t1y)), max(t0z, t1z));
  uvec4 reach = uvec4(lessThanEqual(entry, leave)) * uvec4(greaterThanEqual(leave, vec4(-pad))) *
                uvec4(lessThanEqual(entry, vec4(searchBest + pad)));
  return equal(reach, uvec4(1u));
}

// One child slot of the node being visited: the nearest child reached goes
// on as `next`, the others onto the stack. Slots past the node's child count
// hold an empty box (lo +inf, hi -inf), which the min/max slab test would
// not reject, so they are skipped by the count.
void considerWideChild(bool reach, float entry, uint slot, uint base, uint childCount, inout uint next,
                       inout float nextEntry) {
  if (!reach || slot >= childCount) return;
  uint child = wideNodes[base + WIDE_CHILD_WORDS + slot / 4u][slot % 4u];
  if (entry < nextEntry) {
    if (nextEntry != 1.0 / 0.0) pushWideChild(next, nextEntry);
    next = child;
    nextEntry = entry;
  } else {
    pushWideChild(child, entry);
  }
}

// Visits inner node `node`: tests its eight boxes at once (two vec4s per
// plane) and returns whether a child goes on as `next`.
bool visitWideNode(uint node, Ray ray, vec3 inverse, float pad, out uint next) {
  if (COUNTERS) ++searchNodes;
  uint base = node * WIDE_NODE_VEC4S;
  uint childCount = wideNodes[base + WIDE_CHILD_COUNT].x;
  vec4 entryLow, entryHigh;
  bvec4 low = wideBoxesReachable(base, 0u, ray, inverse, pad, entryLow);
  bvec4 high = wideBoxesReachable(base, 1u, ray, inverse, pad, entryHigh);
  float nextEntry = 1.0 / 0.0;
  next = 0u;
  for (uint i = 0u; i < 4u; ++i) {
    considerWideChild(low[i], entryLow[i], i, base, childCount, next, nextEntry);
    considerWideChild(high[i], entryHigh[i], i + 4u, base, childCount, next, nextEntry);
  }
  return nextEntry != 1.0 / 0.0;
}

// The next child on the stack the ray may still meet nearer than the best
// hit (+ pad), or false when none is left.
bool popWideChild(float pad, out uint child) {
  while (wideStackTop > 0) {
    --wideStackTop;
    if (wideStackEntry[wideStackTop] <= searchBest + pad) {
      child = wideStackChild[wideStackTop];
      return true;
    }
  }
  child = 0u;
  return false;
}

// With the wide BVH: the nearest hit of brute force, as nearestHitInBvh()
// argues. The stack holds at most seven children per level below the root
// (WIDE_STACK_SIZE, from the tree's depth).
RaycastHit nearestHitInWideBvh(Ray ray) {
  beginSearch();
  vec3 inverse = inverseDirection(toFloat3(ray.direction));
  float pad = traversalPad(toFloat3(ray.origin));
  wideStackTop = 0;
  uint current = 0u;  // the root, an inner node
  bool haveCurrent = true;
  while (haveCurrent || popWideChild(pad, current)) {
    if ((current & WIDE_LEAF_BIT) != 0u) {
      testLeaf(ray, (current & WIDE_BLOCK_MASK) * WIDE_WIDTH, ((current >> 28) & 7u) + 1u);
      haveCurrent = false;
    } else {
      haveCurrent = visitWideNode(current, ray, inverse, pad, current);
    }
  }
  return hitRecord(ray, toReal(searchBest), searchBestIndex);
}

// The grid (--gpu-bvh grid) ==================================================================

// The distance along the ray to the plane of cell boundary `k` of one axis
// (origin + k * side: exact, the side a power of two and the origin a
// multiple of it, so the build and the shader agree on every cell).
float gridPlaneDistance(int k, float gridOrigin, float origin, float inverse) {
  return (gridOrigin + float(k) * GRID_CELL_SIZE - origin) * inverse;
}

// The grid's spheres kept apart (too large for its cells): leaf slots
// 0 .. GRID_APART_COUNT - 1, in index order, before the walk.
void testSpheresKeptApart(Ray ray) {
  for (uint k = 0u; k < uint(GRID_APART_COUNT); ++k) {
    if (COUNTERS) ++searchSpheres;
    testLeafSphere(ray, k);
  }
}

// With the grid: the nearest hit of brute force. The spheres kept apart
// (too large for the cells) are tested first, in index order; then the ray
// steps through the cells it crosses in order (Amanatides and Woo's walk,
// each boundary's distance computed afresh rather than summed), tests every
// sphere a cell lists, and stops once the next cell starts farther than the
// best hit + pad. A cell lists every sphere whose surface passes within
// that sphere's own traversal pad (and 2^-8 of a cell) of it, so a sphere
// the float test hits at t is listed by a cell the ray crosses near t; the
// pad here is that of the largest radius and |coordinate| the cells list
// (SphereGrid::walkPad), so it covers every sphere the walk could still meet
// behind its stop. An exact tie still goes to the lower index, whichever
// list a sphere came from (docs/render-model.md section 3, "The grid").
// One loop iteration tests one sphere or steps into one cell, so that the
// invocations of a subgroup whose cells list different numbers of spheres
// go on together instead of each cell waiting for the subgroup's longest
// list: 1.11x faster at 10,000 spheres on the H200 than a sphere loop
// inside the cell loop (docs/experiments/gpu-traversal.md).
RaycastHit nearestHitInGrid(Ray ray) {
  beginSearch();
  testSpheresKeptApart(ray);
  vec3 origin = toFloat3(ray.origin);
  vec3 inverse = inverseDirection(toFloat3(ray.direction));
  float pad = traversalPad(origin);
  vec3 gridOrigin = vec3(GRID_ORIGIN_X, GRID_ORIGIN_Y, GRID_ORIGIN_Z);
  ivec3 cells = ivec3(GRID_CELLS_X, GRID_CELLS_Y, GRID_CELLS_Z);
  // The grid's box reaches past every listed sphere's surface by its margin,
  // as a binary node's box past its spheres: the same slab test clips the
  // ray, and skips the cells where a sphere kept apart is hit before them.
  float enter;
  if (!prewidenedBoxReachable(gridOrigin, gridOrigin + vec3(cells) * GRID_CELL_SIZE, ray, inverse, pad, searchBest,
                              enter)) {
    return hitRecord(ray, toReal(searchBest), searchBestIndex);
  }
  vec3 start = enter > 0.0 ? origin + enter * toFloat3(ray.direction) : origin;
  ivec3 cell = clamp(ivec3(floor((start - gridOrigin) * (1.0 / GRID_CELL_SIZE))), ivec3(0), cells - 1);
  ivec3 step = ivec3(greaterThanEqual(inverse, vec3(0.0))) * 2 - 1;
  ivec3 ahead = max(step, ivec3(0));  // the boundary ahead of a cell: its own (-) or the next one's (+)
  vec3 next = vec3(gridPlaneDistance(cell.x + ahead.x, gridOrigin.x, origin.x, inverse.x),
                   gridPlaneDistance(cell.y + ahead.y, gridOrigin.y, origin.y, inverse.y),
                   gridPlaneDistance(cell.z + ahead.z, gridOrigin.z, origin.z, inverse.z));
  int number = (cell.z * cells.y + cell.y) * cells.x + cell.x;
  ivec3 stride = step * ivec3(1, cells.x, cells.x * cells.y);
  uvec2 listed = gridCells[number];  // first slot, sphere count
  uint slot = listed.x;
  uint end = listed.x + listed.y;
  if (COUNTERS) ++searchNodes;
  while (true) {
    if (slot < end) {
      if (COUNTERS) ++searchSpheres;
      testLeafSphere(ray, slot);
      ++slot;
      continue;
    }
    if (min(min(next.x, next.y), next.z) > searchBest + pad) break;
    if (next.x <= next.y && next.x <= next.z) {
      cell.x += step.x;
      if (uint(cell.x) >= uint(cells.x)) break;
      number += stride.x;
      next.x = gridPlaneDistance(cell.x + ahead.x, gridOrigin.x, origin.x, inverse.x);
    } else if (next.y <= next.z) {
      cell.y += step.y;
      if (uint(cell.y) >= uint(cells.y)) break;
      number += stride.y;
      next.y = gridPlaneDistance(cell.y + ahead.y, gridOrigin.y, origin.y, inverse.y);
    } else {
      cell.z += step.z;
      if (uint(cell.z) >= uint(cells.z)) break;
      number += stride.z;
      next.z = gridPlaneDistance(cell.z + ahead.z, gridOrigin.z, origin.z, inverse.z);
    }
    listed = gridCells[number];
    slot = listed.x;
    end = listed.x + listed.y;
    if (COUNTERS) ++searchNodes;
  }
  return hitRecord(ray, toReal(searchBest), searchBestIndex);
}

// The one spatial query of the shader; the variant is fixed per pipeline.
RaycastHit nearestHit(Ray ray) {
  if (!USE_BVH) return nearestHitOfAll(ray);
  if (GRID) return nearestHitInGrid(ray);
  return WIDE_BVH ? nearestHitInWideBvh(ray) : nearestHitInBvh(ray);
}
