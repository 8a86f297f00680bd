#version 450
#extension GL_GOOGLE_include_directive : require
// The render model of docs/render-model.md (sections 2-5 and 7) as a compute
// shader, one invocation per pixel. It mirrors src/render/scalar/scalar_model.h
// function by function, in the same operation order, so that the GPU image
// agrees with the sequential renderer (docs/render-model.md section 8). Change both together.
// The functions carry the scalar kernel's names (docs/render-model.md section 9).

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
// rt::Bvh::maxRadius and maxCoordinate, which size the traversal pad.
layout(constant_id = RT_SPEC_BVH_MAX_RADIUS) const float BVH_MAX_RADIUS = 0.0;
layout(constant_id = RT_SPEC_BVH_MAX_COORDINATE) const float BVH_MAX_COORDINATE = 0.0;

const float EPS = float(RT_HIT_EPSILON);

// Inputs =====================================================================
// Mirrored by rt::gpu::GPUSphere (src/gpu/compute/gpu_layout.h): std430, 32 bytes,
// {vec3 position; float radius; vec3 color; float pad} byte for byte. Read
// as two vec4s: the intersection loop then fetches each sphere with one
// 16-byte load per invocation instead of four scalar ones (lavapipe
// gathers storage-buffer loads lane by lane: random100 1.3x faster).
struct GPUSphere {
  vec4 positionRadius;  // xyz: position, w: radius
  vec4 colorPad;        // rgb: color, a: padding
};

layout(std430, set = 0, binding = RT_BINDING_SPHERES) readonly buffer Spheres {
  GPUSphere spheres[];
};

// Mirrored by rt::BvhNode (src/render/accel/bvh.h, asserted in
// src/gpu/compute/gpu_layout.h): 32 bytes, {vec3 lo; uint first; vec3 hi; uint meta}.
// Read as two uvec4s for the same one-load-per-half reason as GPUSphere;
// uints, not floats, so that the counts and indices (denormals as floats)
// come through untouched, and the bounds are reinterpreted as floats.
struct GPUBvhNode {
  uvec4 loFirst;  // xyz: lower bounds, w: first (leaf: slot in order, inner: left child)
  uvec4 hiMeta;   // xyz: upper bounds, w: leaf sphere count, or split axis << 30
};

// With brute force these slots name the sphere buffer and are never read.
layout(std430, set = 0, binding = RT_BINDING_BVH_NODES) readonly buffer BvhNodes {
  GPUBvhNode bvhNodes[];
};
layout(std430, set = 0, binding = RT_BINDING_BVH_ORDER) readonly buffer BvhOrder {
  uint bvhOrder[];  // sphere indices, leaf by leaf
};

layout(rgba8, set = 0, binding = RT_BINDING_OUTPUT) uniform writeonly image2D outputImage;

// The push constants: the camera and the image size per frame, the scene's
// shading parameters and sphere count. Declared from the member list that
// also declares the C++ mirror rt::gpu::FrameConstants (gpu_interface.h).
#define RT_GLSL_MEMBER(type, name, at) layout(offset = at) type name;
layout(push_constant, std430) uniform FrameConstants {
  RT_FRAME_CONSTANTS(RT_GLSL_MEMBER)
} pc;

// Intersection (docs/render-model.md section 3) ==============================================
struct Ray {
  vec3 origin;
  vec3 direction;  // unit
};

struct RaycastHit {
  vec3 position;
  vec3 normal;
  int sphere;  // -1 for a miss
};

// Distance along the ray to one sphere (xyz: centre, w: radius), or a
// value <= EPS for no hit, with the cancellation-free discriminant.
float intersectSphere(Ray ray, vec4 sphere) {
  vec3 oc = ray.origin - sphere.xyz;
  float b = dot(oc, ray.direction);
  vec3 f = oc - b * ray.direction;
  float r = sphere.w;
  float disc = r * r - dot(f, f);
  if (disc < 0.0) return -1.0;
  float h = sqrt(disc);
  float t = -b - h;
  if (t <= EPS) t = -b + h;
  return t;
}

// The hit record of sphere `index` at distance `t` (or a miss for index -1).
RaycastHit hitRecord(Ray ray, float t, int index) {
  RaycastHit hit;
  hit.sphere = index;
  hit.position = vec3(0.0);
  hit.normal = vec3(0.0);
  if (index >= 0) {
    vec4 s = spheres[index].positionRadius;
    hit.position = ray.origin + t * ray.direction;
    hit.normal = (hit.position - s.xyz) / s.w;
    // docs/render-model.md section 4: a ray leaving the sphere sees its inside.
    if (dot(ray.direction, hit.normal) > 0.0) hit.normal = -hit.normal;
  }
  return hit;
}

// Brute force: the nearest hit over all spheres; on an exact tie the lower index wins.
RaycastHit nearestHitOfAll(Ray ray) {
  float best = 1.0 / 0.0;  // +infinity
  int bestIndex = -1;
  for (uint i = 0u; i < pc.sphereCount; ++i) {
    float t = intersectSphere(ray, spheres[i].positionRadius);
    if (t > EPS && t < best) {
      best = t;
      bestIndex = int(i);
    }
  }
  return hitRecord(ray, best, bestIndex);
}

// rt::traversalPad (src/render/accel/bvh.h) for this ray's origin: how far
// a box is widened, in space and along the ray, so that no sphere the float
// test reports a hit on is culled with its box.
float traversalPad(vec3 origin) {
  vec3 a = abs(origin);
  float scale = max(max(a.x, a.y), a.z) + BVH_MAX_COORDINATE;
  return float(RT_BVH_PAD_SCALE) * scale + float(RT_BVH_PAD_TANGENT) * sqrt(BVH_MAX_RADIUS * scale) +
         float(RT_BVH_PAD_RADIUS) * BVH_MAX_RADIUS + float(RT_BVH_PAD_MIN);
}

// 1 / direction, with a zero component made tiny (sign kept, -0 included),
// so that the slab test never computes 0 * infinity, and Vulkan's division
// stays inside the range where its precision is defined.
vec3 inverseDirection(vec3 d) {
  const float tiny = 1e-30;
  uvec3 signs = floatBitsToUint(d) & 0x80000000u;
  vec3 signedTiny = uintBitsToFloat(signs | floatBitsToUint(tiny));
  return 1.0 / mix(d, signedTiny, lessThan(abs(d), vec3(tiny)));
}

// Whether the ray may meet a sphere inside the node's box, widened by
// `pad`, nearer than `best` (+ pad): the CPU kernels' slab test.
bool boxReachable(GPUBvhNode node, Ray ray, vec3 inverse, float pad, float best) {
  vec3 t0 = (uintBitsToFloat(node.loFirst.xyz) - pad - ray.origin) * inverse;
  vec3 t1 = (uintBitsToFloat(node.hiMeta.xyz) + pad - ray.origin) * inverse;
  vec3 near = min(t0, t1);
  vec3 far = max(t0, t1);
  float tmin = max(max(near.x, near.y), near.z);
  float tmax = min(min(far.x, far.y), far.z);
  return tmin <= tmax && tmax >= -pad && tmin <= best + pad;
}

// With the BVH: the same nearest hit as brute force. The same
// intersectSphere gives each sphere the same t; spheres come in tree order,
// so an exact tie is settled by the index rather than by the visit order.
// Near child first, a fixed stack: a node pops before its two children
// push, so depth + 1 entries suffice.
RaycastHit nearestHitInBvh(Ray ray) {
  vec3 inverse = inverseDirection(ray.direction);
  float pad = traversalPad(ray.origin);
  float best = 1.0 / 0.0;  // +infinity
  int bestIndex = -1;
  uint stack[RT_BVH_MAX_DEPTH + 2];
  int top = 0;
  stack[top++] = 0u;
  while (top > 0) {
    GPUBvhNode node = bvhNodes[stack[--top]];
    if (!boxReachable(node, ray, inverse, pad, best)) continue;
    uint first = node.loFirst.w;
    uint count = node.hiMeta.w & RT_BVH_COUNT_MASK;
    if (count == 0u) {
      bool negative = ray.direction[node.hiMeta.w >> 30] < 0.0;
      stack[top++] = first + (negative ? 0u : 1u);  // far child
      stack[top++] = first + (negative ? 1u : 0u);  // near child, visited next
      continue;
    }
    for (uint k = first; k < first + count; ++k) {
      int index = int(bvhOrder[k]);
      float t = intersectSphere(ray, spheres[index].positionRadius);
      if (t > EPS && (t < best || (t == best && index < bestIndex))) {
        best = t;
        bestIndex = index;
      }
    }
  }
  return hitRecord(ray, best, bestIndex);
}

// The one spatial query of the shader; the variant is fixed per pipeline.
RaycastHit nearestHit(Ray ray) {
  return USE_BVH ? nearestHitInBvh(ray) : nearestHitOfAll(ray);
}

// Shading (docs/render-model.md section 4) ===================================================
vec3 localColor(RaycastHit hit, vec3 direction, vec3 sphereColor) {
  vec3 n = hit.normal;
  vec3 l = pc.toLight;
  vec3 ambient = pc.ambientColor * sphereColor;
  vec3 diffuse = max(dot(n, l), 0.0) * pc.lightColor * sphereColor;
  vec3 rr = -l - 2.0 * dot(-l, n) * n;  // reflect(-l, n)
  // GLSL leaves pow(0, 0) undefined (NaN on some GPUs); C++ gives 1.
  // Clamped to [0, 1] as in the scalar model (render model section 4).
  float highlight = pc.shininess == 0.0 ? 1.0 : pow(clamp(dot(rr, -direction), 0.0, 1.0), pc.shininess);
  return ambient + diffuse + pc.specularStrength * highlight * pc.lightColor;
}

// The bounce of docs/render-model.md section 5: offset origin, renormalised mirror direction.
Ray reflectedRay(Ray ray, RaycastHit hit) {
  vec3 d = ray.direction;
  vec3 n = hit.normal;
  return Ray(hit.position + n * EPS, normalize(d - 2.0 * dot(d, n) * n));
}

// The two algorithms (docs/render-model.md section 5) ========================================

// A single-pass bounce that hit a sphere: its light joins the colour, its
// colour filters the throughput, and the ray reflects.
void shadeBounce(RaycastHit hit, inout Ray ray, inout vec3 color, inout vec3 throughput) {
  vec3 sphereColor = spheres[hit.sphere].colorPad.rgb;
  color += throughput * localColor(hit, ray.direction, sphereColor);
  throughput *= pc.reflectivity * sphereColor;
  ray = reflectedRay(ray, hit);
}

vec3 traceSinglePass(Ray ray) {
  vec3 color = vec3(0.0);
  vec3 throughput = vec3(1.0);
  for (int depth = 0; depth < MAX_DEPTH; ++depth) {
    RaycastHit hit = nearestHit(ray);
    if (hit.sphere < 0) {
      color += throughput * pc.background;
      if (BOUNCE_EXIT) break;
      // Without the early exit the dead ray is traced again and adds nothing.
      throughput = vec3(0.0);
      continue;
    }
    shadeBounce(hit, ray, color, throughput);
  }
  return color;
}

// One stored segment of the forward pass: what the backward pass reads.
struct PathSegment {
  Ray ray;
  RaycastHit hit;
  vec3 sphereColor;
};

// One step of the backward pass: the light gathered behind segment `s`
// (`acc`) seen through it.
vec3 foldSegment(vec3 acc, PathSegment s) {
  if (s.hit.sphere < 0) return pc.background;
  return acc * pc.reflectivity * s.sphereColor + localColor(s.hit, s.ray.direction, s.sphereColor);
}

vec3 traceTwoPass(Ray ray) {
  PathSegment segments[MAX_DEPTH];
  int count = 0;
  for (; count < MAX_DEPTH; ++count) {
    segments[count].ray = ray;
    segments[count].hit = nearestHit(ray);
    segments[count].sphereColor = vec3(0.0);
    if (segments[count].hit.sphere < 0) {
      if (BOUNCE_EXIT) {
        ++count;
        break;
      }
      continue;  // a segment after a miss is a miss: the ray stays as it was
    }
    segments[count].sphereColor = spheres[segments[count].hit.sphere].colorPad.rgb;
    ray = reflectedRay(ray, segments[count].hit);
  }
  vec3 acc = vec3(0.0);
  for (int i = count - 1; i >= 0; --i) acc = foldSegment(acc, segments[i]);
  return acc;
}

// Camera and output (docs/render-model.md sections 2 and 7) ==================================
vec3 primaryRayDirection(ivec2 pixel) {
  float w = float(pc.width);
  float h = float(pc.height);
  float th = pc.tanHalfFov;
  float u = (2.0 * (float(pixel.x) + 0.5) / w - 1.0) * th * (w / h);
  float v = (1.0 - 2.0 * (float(pixel.y) + 0.5) / h) * th;
  return pc.cameraForward + u * pc.cameraRight + v * pc.cameraUp;
}

// The camera ray through the pixel's centre.
Ray primaryRay(ivec2 pixel) {
  return Ray(pc.cameraPosition, normalize(primaryRayDirection(pixel)));
}

// Clamp and round(255 c) here, so that the value stored is k / 255 exactly
// and the rgba8 conversion cannot round differently from the CPU renderers.
vec4 toRgba8(vec3 c) {
  return vec4(floor(clamp(c, 0.0, 1.0) * 255.0 + 0.5) / 255.0, 1.0);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  // The grid is rounded up to whole workgroups: skip the overhang.
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  Ray ray = primaryRay(pixel);
  vec3 color = TWO_PASS ? traceTwoPass(ray) : traceSinglePass(ray);
  imageStore(outputImage, pixel, toRgba8(color));
}
