#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
// The ray-tracing pipeline renderer's closest-hit shader: hands the nearest
// sphere and its distance back to the ray-generation shader, which shades.
// The distance is gl_HitTEXT, the value the intersection shader reported:
// a hit attribute written beside the report is not safe, since lavapipe
// (Mesa 25.0) keeps the attribute of a later report that the driver
// rejected as farther (measured: 4 % of the default scene's pixels wrong).
#include "ray_tracing_stages.glsl"

layout(location = RT_PAYLOAD_LOCATION) rayPayloadInEXT TracedHit traced;

void main() {
  traced.t = gl_HitTEXT;
  traced.sphere = gl_PrimitiveID;
}
