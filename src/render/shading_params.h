#pragma once
// The scene's shading parameters (docs/render-model.md sections 4 and 5),
// taken from the scene once per scene by shadingParamsOf(). Every backend
// fills its own form from this one struct (kernel::ShadingInputs,
// simd::FrameParams, gpu::FrameConstants), so the scene -> shading mapping,
// the light's sign included, is written here and nowhere else.
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace rt {

struct ShadingParams {
  glm::vec3 toLight;  // section 4's l: towards the light, -directionalLightDirection
  glm::vec3 lightColor;
  glm::vec3 ambientColor;
  glm::vec3 background;
  float reflectivity;
  float shininess;
  float specularStrength;
  int maxDepth;
};

// Negated in float: exact, so a double-precision form converted from it
// holds the same value as one negated in double.
inline ShadingParams shadingParamsOf(const Scene& scene) {
  return {.toLight = -scene.lightData.directionalLightDirection,
          .lightColor = scene.lightData.directionalLightColor,
          .ambientColor = scene.lightData.ambientLightColor,
          .background = scene.render.background,
          .reflectivity = scene.render.reflectivity,
          .shininess = scene.render.shininess,
          .specularStrength = scene.render.specularStrength,
          .maxDepth = scene.render.maxDepth};
}

}  // namespace rt
