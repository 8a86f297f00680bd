// The render model of docs/render-model.md (sections 2-5 and 7) for the
// GPU renderer: included by raytrace.comp after its inputs are declared. It
// mirrors src/render/scalar/scalar_model.h function by function, in the
// same operation order, so that the GPU image agrees with the sequential
// renderer (docs/render-model.md section 8). Change both together. The
// functions carry the scalar kernel's names (docs/render-model.md section 9).

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

