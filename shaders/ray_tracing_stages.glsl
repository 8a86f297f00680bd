// What the ray-tracing pipeline renderer's stages (raytrace.rgen,
// sphere.rint, sphere.rchit, sphere.rmiss) share: the inputs of every GPU
// renderer (frame_inputs.glsl) and what a trace hands back. Included first,
// after the #version line and the extensions.
#include "gpu_interface.h"
#include "model_constants.h"
#include "frame_inputs.glsl"

// The nearest hit a trace found: the closest-hit shader fills it from the
// intersection shader's distance, the miss shader marks a miss.
struct TracedHit {
  float t;
  int sphere;  // -1 for a miss
};
#define RT_PAYLOAD_LOCATION 0
