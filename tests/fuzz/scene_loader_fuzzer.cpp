// libFuzzer entry point of the scene loader. Any input must either be
// refused with a SceneError (docs/render-model.md section 1, Rejection) or
// give a scene the renderers can take: every number inside the Limits of
// that section, and a camera that stays finite in every frame a run can
// reach. Anything else (another exception, a sanitizer report, a broken
// promise, a text accepted that is not well-formed JSON) is a crash.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <string_view>

#include "rt_schema.h"
#include "scene/camera.h"
#include "scene/scene_loader.h"

namespace {

// Frames a run can reach: --warmup and --frames are at most 1,000,000 each.
constexpr long long kLastReachableFrame = 2'000'000 - 1;

void require(bool promise, const char* what) {
  if (!promise) {
    std::fprintf(stderr, "scene_loader_fuzzer: accepted scene breaks: %s\n", what);
    std::abort();
  }
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool bounded(const glm::dvec3& v) {
  const double m = rt::schema::kSceneMaxMagnitude;
  return finite(v) && std::abs(v.x) <= m && std::abs(v.y) <= m && std::abs(v.z) <= m;
}
bool unit(const glm::vec3& v) { return std::abs(glm::length(v) - 1.0f) < 1e-3f; }

void checkCamera(const rt::Scene& scene) {
  for (const long long frame : {0LL, 1LL, 12'345LL, kLastReachableFrame}) {
    const rt::CameraFrame c = rt::cameraAtFrame(scene.camera, frame);
    require(finite(c.position) && finite(c.forward) && finite(c.right) && finite(c.up), "camera not finite");
    require(unit(c.forward) && unit(c.right) && unit(c.up), "camera basis not unit");
    require(std::isfinite(c.tanHalfFov) && c.tanHalfFov > 0.0f, "field of view");
  }
}

void checkAccepted(const rt::Scene& scene) {
  require(!scene.spheres.empty(), "no spheres");
  require(bounded(scene.camera.position), "camera.position");
  require(!scene.camera.focusPoint || bounded(*scene.camera.focusPoint), "camera.focusPoint");
  require(unit(scene.lightData.directionalLightDirection), "light direction");
  for (const rt::Sphere& s : scene.spheres) {
    require(bounded(glm::dvec3(s.position)), "sphere position");
    require(s.radius >= static_cast<float>(rt::schema::kSceneMinLength) &&
                s.radius <= static_cast<float>(rt::schema::kSceneMaxMagnitude),
            "sphere radius");
  }
  require(scene.render.maxDepth >= 1 && scene.render.maxDepth <= rt::kMaxDepthLimit, "maxDepth");
  checkCamera(scene);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    checkAccepted(rt::parseScene(text, "fuzz.json"));
    // The loader's fast parser reads lazily; nlohmann, which parsed every
    // scene before it, must find an accepted text well-formed too.
    require(nlohmann::json::accept(text), "accepted text nlohmann calls malformed");
  } catch (const rt::SceneError&) {
    // Refused with a message naming the file and the JSON path: the expected outcome.
  }
  return 0;
}
