#pragma once
// The extremes the scene limits still allow (docs/render-model.md section 1,
// Limits): a radius of 1e6 around the camera, spheres at +-1e6, spheres of
// radius 1e-6 (one straight ahead of the camera, so a ray really hits it),
// and 100,000 small spheres. Each renderer must keep NaN and infinity out of
// the picture on them (docs/render-model.md section 4: the clamped
// highlight, the normal facing the ray). Built through the loader, so each is a
// scene a user could write.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/image.h"
#include "render/accel/accel_scenes.h"
#include "rt_schema.h"
#include "scene/scene_loader.h"

namespace rt::test {

inline nlohmann::json extremeSceneBase(nlohmann::json camera, nlohmann::json spheres) {
  return {{"camera", std::move(camera)},
          {"lightData",
           {{"directionalLightDirection", {-1, -1, 1}},
            {"directionalLightColor", {1, 0, 1}},  // a zero channel: 0 * infinity would be NaN
            {"ambientLightColor", {0.1, 0.1, 0.1}}}},
          {"spheres", std::move(spheres)},
          {"render", {{"maxDepth", 8}, {"shininess", 1e6}, {"background", {0.1, 0.15, 0.25}}}}};
}

inline nlohmann::json sphereJson(double x, double y, double z, double radius, double grey) {
  return {{"position", {x, y, z}}, {"radius", radius}, {"color", {grey, 0, 1 - grey}}};
}

// One of the extreme scenes by name (kExtremeSceneNames).
inline Scene extremeScene(const std::string& name) {
  const double big = schema::kSceneMaxMagnitude;
  const double tiny = schema::kSceneMinLength;
  const nlohmann::json ahead = {{"position", {0, 0, 0}}, {"forward", {0, 0, 1}}, {"fov", 60}};
  nlohmann::json spheres = nlohmann::json::array();
  nlohmann::json camera = ahead;
  if (name == "sky-radius-1e6") {
    // The camera inside a sphere of the largest radius, small spheres around it.
    spheres.push_back(sphereJson(0, 0, 0, big, 0.8));
    for (int i = 0; i < 5; ++i) spheres.push_back(sphereJson(-2.0 + i, 0, 2.0 + i, 0.6, 0.2 * i));
    camera = {{"position", {0, 0.5, -3}}, {"forward", {0, 0, 1}}, {"fov", 60}};
  } else if (name == "positions-1e6") {
    // Spheres at the corners of the limit, the camera among those at +1e6.
    for (int i = 0; i < 4; ++i) spheres.push_back(sphereJson(big - 3.0 * i, big - 1.0 * i, big, 1.0, 0.3 * i));
    spheres.push_back(sphereJson(-big, -big, -big, big, 0.5));
    spheres.push_back(sphereJson(big, -big, big, 1.0, 0.9));
    camera = {{"position", {big - 4, big - 1, big - 12}},
              {"focusPoint", {big - 4, big - 1.5, big}},
              {"orbitVelocity", 0.5},
              {"fov", 60}};
  } else if (name == "radius-1e-6") {
    // Spheres of the smallest radius, one on the optical axis, where the
    // middle pixel's ray of an odd-sized image passes through its centre.
    spheres = {sphereJson(0, 0, 10, tiny, 0.5), sphereJson(0, 0, 1000, tiny, 0.7), sphereJson(0, 0, big, tiny, 0.9),
               sphereJson(1, 0, 20, 1.0, 0.3)};
  } else if (name == "100000-small") {
    for (std::uint32_t i = 0; i < 100'000; ++i) {
      spheres.push_back(sphereJson(40 * unitNoise(i, 1) - 20, 20 * unitNoise(i, 2) - 10, 10 + 40 * unitNoise(i, 3),
                                   0.01 + 0.05 * unitNoise(i, 4), unitNoise(i, 5)));
    }
  }
  return parseScene(extremeSceneBase(camera, spheres).dump(), name + ".json");
}

inline constexpr const char* kExtremeSceneNames[] = {"sky-radius-1e6", "positions-1e6", "radius-1e-6", "100000-small"};

inline std::vector<NamedScene> extremeScenes() {
  std::vector<NamedScene> named;
  for (const char* name : kExtremeSceneNames) named.push_back({name, extremeScene(name)});
  return named;
}

// Odd, so the middle pixel's ray is the camera's forward direction exactly.
inline constexpr Extent kExtremeExtent{33, 25};

}  // namespace rt::test
