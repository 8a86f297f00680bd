// Constants of the render model (docs/render-model.md) shared by C++ and GLSL:
// both languages include this file, so it holds #defines only.
#ifndef RT_MODEL_CONSTANTS_H
#define RT_MODEL_CONSTANTS_H

// Ray offset and minimum hit distance (docs/render-model.md section 3, chosen).
#define RT_HIT_EPSILON 1e-4
// Upper bound of a scene's render.maxDepth (docs/render-model.md section 1).
#define RT_MAX_DEPTH_LIMIT 64

#endif
