// The two algorithms of docs/render-model.md section 5 over one nearest-hit
// query, for every GPU renderer: included after render_model.glsl by a
// shader that defines `RaycastHit nearestHit(Ray ray)` (the compute
// renderer's walk, or the ray-tracing pipeline's traceRayEXT) and
// `void endSearch(int depth, bool hit)` (its counters, or nothing), and the
// specialization constants MAX_DEPTH and BOUNCE_EXIT.

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
    endSearch(depth, hit.sphere >= 0);
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
    endSearch(count, segments[count].hit.sphere >= 0);
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
