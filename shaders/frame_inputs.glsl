// The inputs every GPU renderer's shaders read (the compute renderer's
// raytrace.comp and the ray-tracing pipeline's stages): the spheres, the
// push constants, the output image. Included after gpu_interface.h and
// model_constants.h.

const float EPS = float(RT_HIT_EPSILON);

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

layout(rgba8, set = 0, binding = RT_BINDING_OUTPUT) uniform writeonly image2D outputImage;

// The push constants: the camera and the image size per frame, the scene's
// shading parameters and sphere count. Declared from the member list that
// also declares the C++ mirror rt::gpu::FrameConstants (gpu_interface.h).
#define RT_GLSL_MEMBER(type, name, at) layout(offset = at) type name;
layout(push_constant, std430) uniform FrameConstants {
  RT_FRAME_CONSTANTS(RT_GLSL_MEMBER)
} pc;
