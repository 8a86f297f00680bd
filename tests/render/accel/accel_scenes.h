#pragma once
// Scenes built to break an acceleration structure, and a seeded
// 1000-sphere scene: the BVH must find exactly the nearest hit brute force
// finds in each (docs/render-model.md section 3, the query). Every scene starts from the committed default
// scene's camera, light and shading; only the spheres (and, for the camera
// inside a sphere, the camera) change.
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "test_support.h"

namespace rt::test {

struct NamedScene {
  std::string name;
  Scene scene;
};

inline Scene withSpheres(std::vector<Sphere> spheres) {
  Scene scene = loadNamedScene("default");
  scene.spheres = std::move(spheres);
  return scene;
}

// A small counter-based generator: the same scene on every machine.
inline float unitNoise(std::uint32_t i, std::uint32_t salt) {
  std::uint32_t x = i * 0x9E3779B1u + salt * 0x85EBCA77u;
  x ^= x >> 15;
  x *= 0x2C1B3C6Du;
  x ^= x >> 12;
  return static_cast<float>(x & 0xFFFFFFu) / static_cast<float>(0x1000000);
}

inline std::vector<Sphere> randomSpheres(std::uint32_t count, float halfWidth, float radius) {
  std::vector<Sphere> spheres;
  for (std::uint32_t i = 0; i < count; ++i) {
    const glm::vec3 p{(2 * unitNoise(i, 1) - 1) * halfWidth, (2 * unitNoise(i, 2) - 1) * halfWidth * 0.5f,
                      (2 * unitNoise(i, 3) - 1) * halfWidth};
    spheres.push_back({p, radius * (0.5f + unitNoise(i, 4)), {unitNoise(i, 5), unitNoise(i, 6), unitNoise(i, 7)}});
  }
  return spheres;
}

// A large "sky" sphere around small ones, and the same with the camera
// inside the sky among the small ones: there every secondary ray that
// misses the small spheres leaves the sky from inside (docs/render-model.md
// section 4, the normal facing the ray).
inline Scene skyAroundSmallSpheres() {
  std::vector<Sphere> sky{{{0, 0, 0}, 50, {0.8f, 0.8f, 0.8f}}};
  for (const Sphere& s : randomSpheres(60, 4, 0.3f)) sky.push_back(s);
  return withSpheres(sky);
}

inline Scene cameraInsideSky() {
  Scene inside = skyAroundSmallSpheres();
  inside.camera.position = {0.0, 0.5, -3.0};
  return inside;
}

// The layout of the best-known sphere scene: a ground sphere of radius 1000
// whose top is the plane y = 0, under a field of small spheres resting on it
// and three larger ones. One radius 5,000 times the rest: the scene's
// extremes say nothing of the small spheres' boxes (docs/render-model.md
// section 3, "The traversal pad").
inline Scene groundUnderSmallSpheres() {
  const glm::vec3 ground{0.5f, 0.5f, 0.5f};
  std::vector<Sphere> spheres{{{0, -1000, 0}, 1000, ground}};
  for (std::uint32_t i = 0; i < 196; ++i) {
    const float x = static_cast<float>(i % 14) - 6.5f + 0.6f * (unitNoise(i, 1) - 0.5f);
    const float z = static_cast<float>(i / 14) - 6.5f + 0.6f * (unitNoise(i, 2) - 0.5f);
    spheres.push_back({{x, 0.2f, z}, 0.2f, {unitNoise(i, 3), unitNoise(i, 4), unitNoise(i, 5)}});
  }
  for (int i = -1; i <= 1; ++i) spheres.push_back({{4.0f * static_cast<float>(i), 1, 0}, 1, {0.9f, 0.8f, 0.7f}});
  return withSpheres(spheres);
}

inline std::vector<NamedScene> adversarialScenes() {
  std::vector<NamedScene> scenes;
  const glm::vec3 red{0.9f, 0.2f, 0.2f}, blue{0.2f, 0.4f, 0.9f}, grey{0.8f};
  // Exact ties: the lower index must win, as in brute force.
  scenes.push_back({"coincident", withSpheres({{{0, 0, 0}, 1, red},
                                               {{0, 0, 0}, 1, blue},
                                               {{0, 0, 0}, 1, grey},
                                               {{1.5f, 0, 0}, 0.5f, blue},
                                               {{1.5f, 0, 0}, 0.5f, red}})});
  scenes.push_back(
      {"nested",
       withSpheres({{{0, 0, 0}, 2, red}, {{0, 0, 0}, 1.5f, blue}, {{0.2f, 0, 0}, 1, grey}, {{0, 0, 0}, 0.5f, red}})});
  std::vector<Sphere> touching;
  for (int i = 0; i < 12; ++i) touching.push_back({{-5.5f + static_cast<float>(i), 0, 0}, 0.5f, i % 2 ? red : blue});
  scenes.push_back({"touching", withSpheres(touching)});
  scenes.push_back({"huge-around-small", skyAroundSmallSpheres()});
  scenes.push_back({"camera-inside", cameraInsideSky()});
  // Centres and tangents on the planes of a grid of power-of-two cells
  // (render/accel/sphere_grid.h): spheres of radius 1 at even coordinates
  // touch their neighbours on odd planes, and eight at odd coordinates
  // touch even planes.
  std::vector<Sphere> onPlanes;
  for (int i = 0; i < 27; ++i) {
    const glm::vec3 p(static_cast<float>(2 * (i % 3 - 1)), static_cast<float>(2 * (i / 3 % 3 - 1)),
                      static_cast<float>(2 * (i / 9 - 1)));
    onPlanes.push_back({p, 1, i % 2 ? red : grey});
  }
  for (int i = 0; i < 8; ++i) {
    onPlanes.push_back({{i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f}, 1, blue});
  }
  scenes.push_back({"on-cell-planes", withSpheres(onPlanes)});
  scenes.push_back({"ground-under-small", groundUnderSmallSpheres()});
  scenes.push_back({"random1000", withSpheres(randomSpheres(1000, 12, 0.4f))});
  return scenes;
}

}  // namespace rt::test
