#pragma once
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

#include "model_constants.h"

namespace rt {

// Scene model of docs/render-model.md section 1; field names follow the thesis.
// Camera set-up runs in double; per-pixel work is float.
struct CameraSpec {
  glm::dvec3 position{0.0};
  glm::dvec3 forward{0.0, 0.0, 1.0};  // unit; derived from focusPoint when absent
  double fov = 60.0;                  // degrees, vertical
  std::optional<glm::dvec3> focusPoint;
  double orbitVelocity = 0.0;  // radians per second of animation time

  [[nodiscard]] bool orbits() const { return orbitVelocity != 0.0; }
};

struct LightData {
  glm::vec3 directionalLightDirection{0.0f, -1.0f, 0.0f};  // unit; the way light travels
  glm::vec3 directionalLightColor{1.0f};
  glm::vec3 ambientLightColor{0.1f};
};

struct Sphere {
  glm::vec3 position{0.0f};
  float radius = 1.0f;
  glm::vec3 color{1.0f};
};

struct RenderParams {
  int maxDepth = 5;
  float reflectivity = 0.5f;
  float shininess = 32.0f;
  float specularStrength = 0.5f;
  glm::vec3 background{0.0f};
};

inline constexpr int kMaxDepthLimit = RT_MAX_DEPTH_LIMIT;

struct Scene {
  std::string name;  // file stem, e.g. "random100"
  // SHA-256 of the text the scene was parsed from: the run metadata records
  // what was rendered without opening the file again (a pipe reads once).
  std::string sha256;
  CameraSpec camera;
  LightData lightData;
  std::vector<Sphere> spheres;  // contiguous: the renderers walk it per ray
  RenderParams render;
};

}  // namespace rt
