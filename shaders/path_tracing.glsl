// The two algorithms of docs/render-model.md section 5 over one nearest-hit
// query, for every GPU renderer: included after render_model.glsl by a
// shader that defines `RaycastHit nearestHit(Ray ray)` (the compute
// renderer's walk, or the ray-tracing pipeline's traceRayEXT) and
// `void endSearch(int depth, bool hit)` (its counters, or nothing), and the
// specialization constants MAX_DEPTH and BOUNCE_EXIT.

// The two algorithms (docs/render-model.md section 5) ========================================

// A single-pass bounce that hit a sphere: its light joins the colour, its
// colour filters the throughput, and the ray reflects.
void shadeBounce(RaycastHit hit, inout Ray ray, inout real3 color, inout real3 throughput) {
  real3 sphereColor = toReal3(spheres[hit.sphere].colorPad.rgb);
  color += throughput * localColor(hit, ray.direction, sphereColor);
  throughput *= toReal(pc.reflectivity) * sphereColor;
  ray = reflectedRay(ray, hit);
}

real3 traceSinglePass(Ray ray) {
  real3 color = real3(0.0);
  real3 throughput = real3(1.0);
  for (int depth = 0; depth < MAX_DEPTH; ++depth) {
    RaycastHit hit = nearestHit(ray);
    endSearch(depth, hit.sphere >= 0);
    if (hit.sphere < 0) {
      color += throughput * toReal3(pc.background);
      if (BOUNCE_EXIT) break;
      // Without the early exit the dead ray is traced again and adds nothing.
      throughput = real3(0.0);
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
  real3 sphereColor;
};

// One step of the backward pass: the light gathered behind segment `s`
// (`acc`) seen through it.
real3 foldSegment(real3 acc, PathSegment s) {
  if (s.hit.sphere < 0) return toReal3(pc.background);
  return acc * toReal(pc.reflectivity) * s.sphereColor + localColor(s.hit, s.ray.direction, s.sphereColor);
}

real3 traceTwoPass(Ray ray) {
  PathSegment segments[MAX_DEPTH];
  int count = 0;
  for (; count < MAX_DEPTH; ++count) {
    segments[count].ray = ray;
    segments[count].hit = nearestHit(ray);
    endSearch(count, segments[count].hit.sphere >= 0);
    segments[count].sphereColor = real3(0.0);
    if (segments[count].hit.sphere < 0) {
      if (BOUNCE_EXIT) {
        ++count;
        break;
      }
      continue;  // a segment after a miss is a miss: the ray stays as it was
    }
    segments[count].sphereColor = toReal3(spheres[segments[count].hit.sphere].colorPad.rgb);
    ray = reflectedRay(ray, segments[count].hit);
  }
  real3 acc = real3(0.0);
  for (int i = count - 1; i >= 0; --i) acc = foldSegment(acc, segments[i]);
  return acc;
}
