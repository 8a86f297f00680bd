#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
// The ray-tracing pipeline renderer's miss shader: no sphere was hit.
#include "ray_tracing_stages.glsl"

layout(location = RT_PAYLOAD_LOCATION) rayPayloadInEXT TracedHit traced;

void main() {
  traced.t = 0.0;
  traced.sphere = -1;
}
