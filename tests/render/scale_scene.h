#pragma once
// A random scene of any size generated in the test (a 100,000-sphere scene
// is 12 MB of JSON: too large to commit), with the layout scripts/rtbench/scenes.py
// gives randomN above 100 spheres: random100's disc (radius 9, half height
// 1.5) and camera scaled by cbrt(N / 100), radii 0.25 to 1, so the spheres
// per unit volume stay those of random100. Not randomN's spheres (another
// generator), the same kind of scene.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include "render/accel/accel_scenes.h"

namespace rt::test {

inline Scene randomSceneAtScale(std::uint32_t count) {
  Scene scene = loadNamedScene("random100");
  const float s = std::cbrt(static_cast<float>(count) / 100.0f);
  const float spread = 9.0f * s;
  const float halfHeight = 1.5f * s;
  scene.name = "random" + std::to_string(count) + "-test";
  scene.camera.position *= static_cast<double>(s);
  scene.spheres.clear();
  scene.spheres.reserve(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    const float radius = 0.25f + 0.75f * unitNoise(i, 11);
    const float r = (spread - radius) * std::sqrt(unitNoise(i, 12));
    const float angle = 2.0f * std::numbers::pi_v<float> * unitNoise(i, 13);
    const glm::vec3 position{r * std::cos(angle), (2.0f * unitNoise(i, 14) - 1.0f) * halfHeight, r * std::sin(angle)};
    const glm::vec3 color{0.1f + 0.9f * unitNoise(i, 15), 0.1f + 0.9f * unitNoise(i, 16),
                          0.1f + 0.9f * unitNoise(i, 17)};
    scene.spheres.push_back({position, radius, color});
  }
  return scene;
}

}  // namespace rt::test
