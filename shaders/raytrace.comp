#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#if RT_PRECISION_F16
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require
#endif
// The GPU renderer: the render model (render_model.glsl, nearest_hit.glsl)
// traced by one of four pipelines of this shader (docs/render-model.md
// section 3, "How the GPU renderer walks the BVH"):
// - the megakernel: each invocation follows a pixel's path through every
//   bounce, one invocation per pixel or, with persistent threads, as many
//   paths as its subgroup fetches;
// - per-bounce wavefronts: one dispatch per bounce depth traces a queue of
//   rays and queues the reflected ones (only the live ones with the bounce
//   exit), and a last dispatch writes the image.
// Every pipeline computes each pixel with the same operations in the same
// order, so all of them give the same bytes. Built twice: RT_PRECISION_F16 1
// computes the model in half precision (--precision f16, render_model.glsl).

#include "bvh_layout.h"
#include "gpu_interface.h"
#include "model_constants.h"

layout(local_size_x = RT_WORKGROUP_SIZE_X, local_size_y = RT_WORKGROUP_SIZE_Y) in;

// Variant selection (the C++ kernel's template parameters) ===================
layout(constant_id = RT_SPEC_TWO_PASS) const bool TWO_PASS = false;
layout(constant_id = RT_SPEC_BOUNCE_EXIT) const bool BOUNCE_EXIT = true;
// The scene's render.maxDepth: a specialization constant rather than a push
// constant because it sizes the two-pass algorithm's stored arrays.
layout(constant_id = RT_SPEC_MAX_DEPTH) const int MAX_DEPTH = 5;
// --accel bvh: walk the hierarchy instead of testing every sphere. Off, the
// traversal is compiled out and brute force runs exactly as without it.
layout(constant_id = RT_SPEC_USE_BVH) const bool USE_BVH = false;
// The binary walk's stack size, from the tree's depth (nearestHitInBvh()).
layout(constant_id = RT_SPEC_BVH_STACK_SIZE) const int BVH_STACK_SIZE = RT_BVH_MAX_DEPTH + 2;
// rt::Bvh::pad, the model of the traversal pad (rt::TraversalPadModel).
layout(constant_id = RT_SPEC_BVH_PAD_RADIUS) const float BVH_PAD_RADIUS = 0.0;
layout(constant_id = RT_SPEC_BVH_PAD_COORDINATE) const float BVH_PAD_COORDINATE = 0.0;
layout(constant_id = RT_SPEC_BVH_PAD_ORIGIN_SLOPE) const float BVH_PAD_ORIGIN_SLOPE = 0.0;


// --gpu-bvh wide: walk rt::WideBvh instead of the binary tree; its stack
// size, from the tree's depth (nearestHitInWideBvh()).
layout(constant_id = RT_SPEC_WIDE_BVH) const bool WIDE_BVH = false;
layout(constant_id = RT_SPEC_WIDE_STACK_SIZE) const int WIDE_STACK_SIZE = 1;
// --gpu-schedule persistent: subgroups fetch their rays from a counter.
// --gpu-bvh grid: rt::SphereGrid's corner, cell side (a power of two) and
// cells per axis.
layout(constant_id = RT_SPEC_GRID) const bool GRID = false;
layout(constant_id = RT_SPEC_GRID_ORIGIN_X) const float GRID_ORIGIN_X = 0.0;
layout(constant_id = RT_SPEC_GRID_ORIGIN_Y) const float GRID_ORIGIN_Y = 0.0;
layout(constant_id = RT_SPEC_GRID_ORIGIN_Z) const float GRID_ORIGIN_Z = 0.0;
layout(constant_id = RT_SPEC_GRID_CELL_SIZE) const float GRID_CELL_SIZE = 1.0;
layout(constant_id = RT_SPEC_GRID_CELLS_X) const int GRID_CELLS_X = 1;
layout(constant_id = RT_SPEC_GRID_CELLS_Y) const int GRID_CELLS_Y = 1;
layout(constant_id = RT_SPEC_GRID_CELLS_Z) const int GRID_CELLS_Z = 1;
// The spheres it keeps apart: leaf slots 0 .. GRID_APART_COUNT - 1, tested
// by every ray before the walk.
layout(constant_id = RT_SPEC_GRID_APART_COUNT) const int GRID_APART_COUNT = 0;
layout(constant_id = RT_SPEC_PERSISTENT) const bool PERSISTENT = false;
// RT_STAGE_*: the megakernel, or a wavefront's depth or resolve dispatch.
layout(constant_id = RT_SPEC_STAGE) const int STAGE = RT_STAGE_MEGAKERNEL;
// --counters: tally rays, visits, tests and lane slots (nearest_hit.glsl).
layout(constant_id = RT_SPEC_COUNTERS) const bool COUNTERS = false;

// Inputs =====================================================================
#include "frame_inputs.glsl"

// --accel bvh, --gpu-bvh binary: rt::gpu::GpuBinaryNode (gpu_layout.h),
// 64 bytes per inner node of rt::Bvh holding its two children's boxes, as
// four uvec4s: {child 0's lo, its word}, {child 0's hi, its leaf sphere
// count (0: inner)}, and the same for child 1. uints, not floats, so that
// the words and counts (denormals as floats) come through untouched; the
// bounds are reinterpreted as floats.
// Slots a variant does not use name the sphere buffer and are never read.
layout(std430, set = 0, binding = RT_BINDING_BVH_NODES) readonly buffer BvhNodes {
  uvec4 bvhNodes[];
};
layout(std430, set = 0, binding = RT_BINDING_BVH_ORDER) readonly buffer BvhOrder {
  uint bvhOrder[];  // sphere indices, leaf by leaf
};
// The spheres of the BVH's leaves (position, radius) in leaf order: the
// binary tree's order, or the wide tree's leaf slots; a leaf's spheres are
// read without going through their indices, which are read only for a hit.
layout(std430, set = 0, binding = RT_BINDING_LEAF_SPHERES) readonly buffer LeafSpheres {
  vec4 leafSpheres[];
};

// The wide BVH's nodes (16 uvec4s each, nearest_hit.glsl) and the scene
// index of each leaf slot.
layout(std430, set = 0, binding = RT_BINDING_WIDE_NODES) readonly buffer WideNodes {
  uvec4 wideNodes[];
};
layout(std430, set = 0, binding = RT_BINDING_WIDE_INDEX) readonly buffer WideIndex {
  int wideIndex[];
};

// --gpu-bvh grid: each cell's first slot and sphere count (rt::SphereGrid;
// its slots' spheres and scene indices are leafSpheres and bvhOrder).
layout(std430, set = 0, binding = RT_BINDING_GRID_CELLS) readonly buffer GridCells {
  uvec2 gridCells[];
};

layout(std430, set = 0, binding = RT_BINDING_COUNTERS) buffer Counters {
  uint counterWords[];  // RT_COUNTER_COPIES x RT_COUNTER_SLOTS x (low, high)
};

// A queued ray of a wavefront: origin and direction, and in the origin's w
// the ray's number (tile order), which names its path state.
struct QueuedRay {
  vec4 originRay;
  vec4 direction;
};
layout(std430, set = 0, binding = RT_BINDING_QUEUE_EVEN) buffer QueueEven {
  QueuedRay queueEven[];
};
layout(std430, set = 0, binding = RT_BINDING_QUEUE_ODD) buffer QueueOdd {
  QueuedRay queueOdd[];
};
// Single-pass: each path's colour and throughput between its dispatches.
// Two-pass: the segment count in color.w (as uint bits).
struct PathState {
  vec4 color;
  vec4 throughput;
};
layout(std430, set = 0, binding = RT_BINDING_PATH_STATE) buffer PathStates {
  PathState pathStates[];
};
// Two-pass: the forward pass's segments, depth by depth (what the
// backward pass reads: the ray's direction, the sphere hit, the normal).
struct StoredSegment {
  vec4 directionSphere;  // w: the sphere's index as int bits, -1 for a miss
  vec4 normal;
};
layout(std430, set = 0, binding = RT_BINDING_SEGMENTS) buffer Segments {
  StoredSegment segments[];
};
// RT_CONTROL_WORDS per depth (gpu_interface.h).
layout(std430, set = 0, binding = RT_BINDING_CONTROL) buffer Control {
  uint controlWords[];
};

#include "render_model.glsl"
#include "nearest_hit.glsl"

#include "path_tracing.glsl"

// Rays and pixels ============================================================================
// Rays are numbered in 8x8 tiles (gpu_interface.h); the image's overhang
// to whole tiles has numbers but no pixels.
uint tilesAcross() { return (uint(pc.width) + RT_TILE_SIZE - 1u) / RT_TILE_SIZE; }
uint rayCount() { return tilesAcross() * ((uint(pc.height) + RT_TILE_SIZE - 1u) / RT_TILE_SIZE) * RT_TILE_RAYS; }

ivec2 pixelOfRay(uint ray) {
  uint tile = ray / RT_TILE_RAYS;
  uint within = ray % RT_TILE_RAYS;
  return ivec2((tile % tilesAcross()) * RT_TILE_SIZE + within % RT_TILE_SIZE,
               (tile / tilesAcross()) * RT_TILE_SIZE + within / RT_TILE_SIZE);
}

uint rayOfPixel(ivec2 pixel) {
  uvec2 p = uvec2(pixel);
  uint tile = (p.y / RT_TILE_SIZE) * tilesAcross() + p.x / RT_TILE_SIZE;
  return tile * RT_TILE_RAYS + (p.y % RT_TILE_SIZE) * RT_TILE_SIZE + p.x % RT_TILE_SIZE;
}

bool insideImage(ivec2 pixel) { return pixel.x < pc.width && pixel.y < pc.height; }

// The megakernel ==============================================================================
void renderPixel(ivec2 pixel) {
  Ray ray = primaryRay(pixel);
  real3 color = TWO_PASS ? traceTwoPass(ray) : traceSinglePass(ray);
  imageStore(outputImage, pixel, toRgba8(color));
}

// Per-bounce wavefronts =======================================================================
uint controlWord(int depth, uint word) { return uint(depth) * RT_CONTROL_WORDS + word; }

// The rays queued for `depth`: all of them at depth 0, where the camera
// makes them; later, as many as the depth before queued.
uint queuedRays(int depth) { return depth == 0 ? rayCount() : controlWords[controlWord(depth, RT_CONTROL_COUNT)]; }

// Member by member: glslang makes invalid SPIR-V of a ?: between the two blocks' structs.
Ray queuedRay(int depth, uint slot, out uint number) {
  vec4 origin = (depth & 1) == 0 ? queueEven[slot].originRay : queueOdd[slot].originRay;
  vec4 direction = (depth & 1) == 0 ? queueEven[slot].direction : queueOdd[slot].direction;
  number = floatBitsToUint(origin.w);
  return Ray(toReal3(origin.xyz), toReal3(direction.xyz));
}

// Queues `ray` (number `number`) for depth + 1. The subgroup's invocations
// that queue take consecutive slots with one atomicAdd, and the next
// dispatch's size grows to cover them.
void queueRay(int depth, Ray ray, uint number) {
  uvec4 queuing = subgroupBallot(true);
  uint count = subgroupBallotBitCount(queuing);
  uint base = 0u;
  if (subgroupElect()) {
    base = atomicAdd(controlWords[controlWord(depth + 1, RT_CONTROL_COUNT)], count);
    uint raysPerRow = RT_WAVEFRONT_GROUPS_X * RT_TILE_RAYS;
    atomicMax(controlWords[controlWord(depth + 1, RT_CONTROL_GROUPS_Y)], (base + count + raysPerRow - 1u) / raysPerRow);
  }
  uint slot = subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(queuing);
  QueuedRay queued = QueuedRay(vec4(toFloat3(ray.origin), uintBitsToFloat(number)), vec4(toFloat3(ray.direction), 0.0));
  if (((depth + 1) & 1) == 0) {
    queueEven[slot] = queued;
  } else {
    queueOdd[slot] = queued;
  }
}

// The single-pass algorithm's step at `depth` for one path: traceSinglePass's
// loop body, with the colour and throughput kept in the path's state.
void stepSinglePass(int depth, Ray ray, uint number) {
  real3 color = real3(0.0);
  real3 throughput = real3(1.0);
  if (depth > 0) {
    color = toReal3(pathStates[number].color.rgb);
    throughput = toReal3(pathStates[number].throughput.rgb);
  }
  RaycastHit hit = nearestHit(ray);
  endSearch(depth, hit.sphere >= 0);
  bool goesOn = depth + 1 < MAX_DEPTH;
  if (hit.sphere < 0) {
    color += throughput * toReal3(pc.background);
    // Without the early exit the dead ray is traced again and adds nothing.
    throughput = real3(0.0);
    goesOn = goesOn && !BOUNCE_EXIT;
  } else {
    shadeBounce(hit, ray, color, throughput);
  }
  pathStates[number] = PathState(vec4(toFloat3(color), 0.0), vec4(toFloat3(throughput), 0.0));
  if (goesOn) queueRay(depth, ray, number);
}

// The two-pass algorithm's forward step at `depth`: traceTwoPass's first
// loop, its segment stored for the resolve dispatch's backward pass.
void stepTwoPass(int depth, Ray ray, uint number) {
  RaycastHit hit = nearestHit(ray);
  endSearch(depth, hit.sphere >= 0);
  uint rayCapacity = rayCount();
  segments[uint(depth) * rayCapacity + number] =
      StoredSegment(vec4(toFloat3(ray.direction), intBitsToFloat(hit.sphere)), vec4(toFloat3(hit.normal), 0.0));
  pathStates[number].color.w = uintBitsToFloat(uint(depth + 1));
  bool goesOn = depth + 1 < MAX_DEPTH;
  if (hit.sphere < 0) {
    goesOn = goesOn && !BOUNCE_EXIT;  // a segment after a miss is a miss: the ray stays as it was
  } else {
    ray = reflectedRay(ray, hit);
  }
  if (goesOn) queueRay(depth, ray, number);
}

// One queued ray of the wavefront at depth pc.wavefrontDepth (slot in its
// queue); at depth 0 the camera's ray of ray number `slot`.
void traceQueuedRay(uint slot) {
  int depth = pc.wavefrontDepth;
  Ray ray;
  uint number = slot;
  if (depth == 0) {
    ivec2 pixel = pixelOfRay(number);
    if (!insideImage(pixel)) return;
    ray = primaryRay(pixel);
  } else {
    ray = queuedRay(depth, slot, number);
  }
  if (TWO_PASS) {
    stepTwoPass(depth, ray, number);
  } else {
    stepSinglePass(depth, ray, number);
  }
}

// The wavefront's last dispatch: the pixel's colour (single-pass), or the
// backward pass over its stored segments (two-pass), as traceTwoPass folds them.
real3 resolvedColor(uint number) {
  if (!TWO_PASS) return toReal3(pathStates[number].color.rgb);
  int count = int(floatBitsToUint(pathStates[number].color.w));
  uint rayCapacity = rayCount();
  real3 acc = real3(0.0);
  for (int i = count - 1; i >= 0; --i) {
    StoredSegment stored = segments[uint(i) * rayCapacity + number];
    PathSegment s;
    s.ray = Ray(real3(0.0), toReal3(stored.directionSphere.xyz));
    s.hit = RaycastHit(real3(0.0), toReal3(stored.normal.xyz), floatBitsToInt(stored.directionSphere.w));
    s.sphereColor = s.hit.sphere < 0 ? real3(0.0) : toReal3(spheres[s.hit.sphere].colorPad.rgb);
    acc = foldSegment(acc, s);
  }
  return acc;
}

// Schedules ====================================================================================
// This dispatch's work item: a pixel's path (megakernel) or a queued ray.
void runWorkItem(uint item) {
  if (STAGE == RT_STAGE_MEGAKERNEL) {
    ivec2 pixel = pixelOfRay(item);
    if (insideImage(pixel)) renderPixel(pixel);
  } else {
    traceQueuedRay(item);
  }
}

uint workItems() { return STAGE == RT_STAGE_MEGAKERNEL ? rayCount() : queuedRays(pc.wavefrontDepth); }

// Persistent threads: each subgroup takes the next gl_SubgroupSize work
// items with one atomicAdd until none are left. The loop's condition is
// the same for the whole subgroup, which stays together for the fetch.
// A subgroup takes at most twice its fair share: lavapipe runs a dispatch's
// workgroups a few at a time, so its first subgroups would take every item,
// and its compiler ends any invocation's loops after 65535 iterations in
// all. The invocations' shares together hold every item twice over.
void runPersistent() {
  uint items = workItems();
  uint fetch = controlWord(STAGE == RT_STAGE_MEGAKERNEL ? 0 : pc.wavefrontDepth, RT_CONTROL_FETCH);
  uint invocations = gl_NumWorkGroups.x * RT_TILE_RAYS;
  uint rounds = 2u * ((items + invocations - 1u) / invocations);
  for (uint round = 0u; round < rounds; ++round) {
    uint base = 0u;
    if (subgroupElect()) base = atomicAdd(controlWords[fetch], gl_SubgroupSize);
    base = subgroupBroadcastFirst(base);
    if (base >= items) break;
    uint item = base + gl_SubgroupInvocationID;
    if (item < items) runWorkItem(item);
  }
}

void main() {
  beginCounting();
  if (STAGE == RT_STAGE_WAVEFRONT_RESOLVE) {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (insideImage(pixel)) imageStore(outputImage, pixel, toRgba8(resolvedColor(rayOfPixel(pixel))));
  } else if (PERSISTENT) {
    runPersistent();
  } else if (STAGE == RT_STAGE_MEGAKERNEL) {
    // One invocation per pixel, in 8x8 workgroups; the grid is rounded up
    // to whole workgroups, and the overhang does nothing.
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (insideImage(pixel)) renderPixel(pixel);
  } else {
    // A row of RT_WAVEFRONT_GROUPS_X workgroups per RT_WAVEFRONT_GROUPS_X * 64 queued rays.
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint slot = group * RT_TILE_RAYS + gl_LocalInvocationIndex;
    if (slot < workItems()) traceQueuedRay(slot);
  }
  flushCounters();
}
