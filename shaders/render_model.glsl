// The render model of docs/render-model.md (sections 2-5 and 7) for the
// GPU renderer: included by raytrace.comp after its inputs are declared. It
// mirrors src/render/scalar/scalar_model.h function by function, in the
// same operation order, so that the GPU image agrees with the sequential
// renderer (docs/render-model.md section 8). Change both together. The
// functions carry the scalar kernel's names (docs/render-model.md section 9).

// The type of the model's arithmetic (docs/render-model.md section 10):
// float, or float16_t in the SPIR-V built with RT_PRECISION_F16 for
// --precision f16 (the including shader enables
// GL_EXT_shader_explicit_arithmetic_types_float16 there). Every literal and
// input is converted to it explicitly (toReal*, and toFloat* back for
// the BVH walk and the buffers, which stay float): GLSL widens float16_t to float
// silently, but never narrows, so a stray float would either fail to
// compile or show as a float in the SPIR-V.
#ifndef RT_PRECISION_F16
#define RT_PRECISION_F16 0
#endif
#if RT_PRECISION_F16
#define real float16_t
#define real3 f16vec3
#define real4 f16vec4
#define toReal(x) float16_t(x)
#define toReal3(x) f16vec3(x)
#define toReal4(x) f16vec4(x)
#define toFloat(x) float(x)
#define toFloat3(x) vec3(x)
#else
// Conversions vanish here, so the float SPIR-V is the one built before
// the type existed, byte for byte.
#define real float
#define real3 vec3
#define real4 vec4
#define toReal(x) (x)
#define toReal3(x) (x)
#define toReal4(x) (x)
#define toFloat(x) (x)
#define toFloat3(x) (x)
#endif

// Intersection (docs/render-model.md section 3) ==============================================
struct Ray {
  real3 origin;
  real3 direction;  // unit
};

struct RaycastHit {
  real3 position;
  real3 normal;
  int sphere;  // -1 for a miss
};

// Distance along the ray to one sphere (xyz: centre, w: radius), or a
// value <= EPS for no hit, with the cancellation-free discriminant.
real intersectSphere(Ray ray, real4 sphere) {
  real3 oc = ray.origin - sphere.xyz;
  real b = dot(oc, ray.direction);
  real3 f = oc - b * ray.direction;
  real r = sphere.w;
  real disc = r * r - dot(f, f);
  if (disc < real(0.0)) return real(-1.0);
  real h = sqrt(disc);
  real t = -b - h;
  if (t <= toReal(EPS)) t = -b + h;
  return t;
}

// The hit record of sphere `index` at distance `t` (or a miss for index -1).
RaycastHit hitRecord(Ray ray, real t, int index) {
  RaycastHit hit;
  hit.sphere = index;
  hit.position = real3(0.0);
  hit.normal = real3(0.0);
  if (index >= 0) {
    real4 s = toReal4(spheres[index].positionRadius);
    hit.position = ray.origin + t * ray.direction;
    hit.normal = (hit.position - s.xyz) / s.w;
    // docs/render-model.md section 4: a ray leaving the sphere sees its inside.
    if (dot(ray.direction, hit.normal) > real(0.0)) hit.normal = -hit.normal;
  }
  return hit;
}

// Shading (docs/render-model.md section 4) ===================================================
real3 localColor(RaycastHit hit, real3 direction, real3 sphereColor) {
  real3 n = hit.normal;
  real3 l = toReal3(pc.toLight);
  real3 ambient = toReal3(pc.ambientColor) * sphereColor;
  real3 diffuse = max(dot(n, l), real(0.0)) * toReal3(pc.lightColor) * sphereColor;
  real3 rr = -l - real(2.0) * dot(-l, n) * n;  // reflect(-l, n)
  // GLSL leaves pow(0, 0) undefined (NaN on some GPUs); C++ gives 1.
  // Clamped to [0, 1] as in the scalar model (render model section 4).
  real highlight = pc.shininess == 0.0
                       ? real(1.0)
                       : pow(clamp(dot(rr, -direction), real(0.0), real(1.0)), toReal(pc.shininess));
  return ambient + diffuse + toReal(pc.specularStrength) * highlight * toReal3(pc.lightColor);
}

// The bounce of docs/render-model.md section 5: offset origin, renormalised mirror direction.
Ray reflectedRay(Ray ray, RaycastHit hit) {
  real3 d = ray.direction;
  real3 n = hit.normal;
  return Ray(hit.position + n * toReal(EPS), normalize(d - real(2.0) * dot(d, n) * n));
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

// The camera ray through the pixel's centre. Its direction is computed in
// float and normalised in the model's type: pixel coordinates past 2048
// have no half-precision value (docs/render-model.md section 10).
Ray primaryRay(int x, int y) {
  return Ray(toReal3(pc.cameraPosition), normalize(toReal3(primaryRayDirection(ivec2(x, y)))));
}

// Clamp and round(255 c) here, so that the value stored is k / 255 exactly
// and the rgba8 conversion cannot round differently from the CPU renderers.
vec4 toRgba8(real3 color) {
  return vec4(floor(clamp(toFloat3(color), 0.0, 1.0) * 255.0 + 0.5) / 255.0, 1.0);
}

