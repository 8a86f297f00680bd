// Constants of the render model (render-model.md) shared by C++ and GLSL:
// both languages include this file, so it holds #defines only.
#ifndef RT_MODEL_CONSTANTS_H
#define RT_MODEL_CONSTANTS_H

// Ray offset and minimum hit distance (spec section 3, chosen).
#define RT_HIT_EPSILON 1e-4
// Upper bound of a scene's render.maxDepth (spec section 1).
#define RT_MAX_DEPTH_LIMIT 64

#endif
