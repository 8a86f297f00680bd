#include "scene/scene_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "core/sha256.h"
#include "test_support.h"

namespace rt {
namespace {

using Json = nlohmann::json;

Json validScene() {
  return Json::parse(R"({
    "camera": {"position": [0, 1, -6], "forward": [0, 0, 2], "fov": 60,
               "focusPoint": [0, 0, 0], "orbitVelocity": 0.5},
    "lightData": {"directionalLightDirection": [-1, -1, 1],
                  "directionalLightColor": [1, 1, 1], "ambientLightColor": [0.1, 0.1, 0.1]},
    "spheres": [{"position": [0, 0, 0], "radius": 1, "color": [0.9, 0.2, 0.2]},
                {"position": [2, 0, 0], "radius": 0.5, "color": [0.2, 0.9, 0.2]}],
    "render": {"maxDepth": 5, "reflectivity": 0.5, "shininess": 32,
               "specularStrength": 0.5, "background": [0, 0, 0]}
  })");
}

Scene parse(const Json& j) { return parseScene(j.dump(), "scenes/test.json"); }

// Parses `text` and returns the rejection's JSON path; fails the test if accepted.
std::string rejectionPath(const std::string& text) {
  try {
    parseScene(text, "scenes/test.json");
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("scenes/test.json"), std::string::npos) << e.what();
    return e.jsonPath();
  }
  ADD_FAILURE() << "accepted: " << text;
  return "<accepted>";
}

std::string rejectionPath(const std::function<void(Json&)>& edit) {
  Json j = validScene();
  edit(j);
  return rejectionPath(j.dump());
}

TEST(SceneLoader, AcceptsValidSceneAndNormalisesDirections) {
  const Scene s = parse(validScene());
  EXPECT_EQ(s.name, "test");
  ASSERT_EQ(s.spheres.size(), 2u);
  EXPECT_FLOAT_EQ(s.spheres[1].radius, 0.5f);
  EXPECT_DOUBLE_EQ(s.camera.forward.z, 1.0);
  EXPECT_NEAR(std::sqrt(3.0) * s.lightData.directionalLightDirection.x, -1.0, 1e-6);
  EXPECT_TRUE(s.camera.orbits());
}

TEST(SceneLoader, RenderBlockAndOrbitAreOptionalWithDefaults) {
  Json j = validScene();
  j.erase("render");
  j["camera"].erase("focusPoint");
  j["camera"].erase("orbitVelocity");
  const Scene s = parse(j);
  EXPECT_EQ(s.render.maxDepth, 5);
  EXPECT_FLOAT_EQ(s.render.reflectivity, 0.5f);
  EXPECT_FLOAT_EQ(s.render.shininess, 32.0f);
  EXPECT_FLOAT_EQ(s.render.specularStrength, 0.5f);
  EXPECT_FALSE(s.camera.orbits());
}

TEST(SceneLoader, ForwardDerivedFromFocusPointWhenAbsent) {
  Json j = validScene();
  j["camera"].erase("forward");
  j["camera"]["position"] = {0, 0, -4};
  const Scene s = parse(j);
  EXPECT_DOUBLE_EQ(s.camera.forward.z, 1.0);
}

// The run metadata's scene.sha256 comes from the text parsed, so a scene
// read from a pipe is not opened a second time (the fuzz driver's FIFO hung).
TEST(SceneLoader, RecordsTheSha256OfTheTextItParsed) {
  const std::string text = validScene().dump();
  EXPECT_EQ(parseScene(text, "scenes/test.json").sha256,
            sha256Hex({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}));
  EXPECT_EQ(test::loadNamedScene("default").sha256, sha256HexOfFile(test::scenePath("default")));
}

TEST(SceneLoader, CommittedScenesLoad) {
  for (const char* name : test::kSceneNames) {
    const Scene s = test::loadNamedScene(name);
    EXPECT_EQ(s.name, name);
    EXPECT_FALSE(s.spheres.empty());
  }
}

TEST(SceneLoader, RejectsMalformedJsonWithLineAndColumn) {
  try {
    parseScene("{\n  \"camera\": {,\n}", "scenes/broken.json");
    FAIL() << "accepted malformed JSON";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scenes/broken.json"), std::string::npos) << what;
    EXPECT_NE(what.find("line 2"), std::string::npos) << what;
  }
}

TEST(SceneLoader, RejectsMissingFile) { EXPECT_THROW(loadScene("/nonexistent/scene.json"), SceneError); }

TEST(SceneLoader, RejectsMissingRequiredFields) {
  EXPECT_EQ(rejectionPath([](Json& j) { j.erase("camera"); }), "camera");
  EXPECT_EQ(rejectionPath([](Json& j) { j.erase("lightData"); }), "lightData");
  EXPECT_EQ(rejectionPath([](Json& j) { j.erase("spheres"); }), "spheres");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"].erase("position"); }), "camera.position");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"].erase("fov"); }), "camera.fov");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][1].erase("radius"); }), "spheres[1].radius");
  EXPECT_EQ(rejectionPath([](Json& j) { j["lightData"].erase("ambientLightColor"); }), "lightData.ambientLightColor");
}

TEST(SceneLoader, RejectsNeitherForwardNorFocusPoint) {
  EXPECT_EQ(rejectionPath([](Json& j) {
              j["camera"].erase("forward");
              j["camera"].erase("focusPoint");
              j["camera"].erase("orbitVelocity");
            }),
            "camera.forward");
}

TEST(SceneLoader, RejectsWrongTypes) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["fov"] = "60"; }), "camera.fov");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"] = Json::array(); }), "camera");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"] = Json::object(); }), "spheres");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][0] = 3; }), "spheres[0]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][0]["radius"] = true; }), "spheres[0].radius");
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["maxDepth"] = 5.5; }), "render.maxDepth");
  EXPECT_EQ(rejectionPath("[1, 2, 3]"), "");
}

TEST(SceneLoader, RejectsVectorsThatAreNotThreeFiniteNumbers) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["position"] = {0, 1}; }), "camera.position");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["position"] = {0, 1, 2, 3}; }), "camera.position");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][0]["position"] = {0, "x", 2}; }), "spheres[0].position[1]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][0]["position"] = 1.0; }), "spheres[0].position");
}

TEST(SceneLoader, RejectsNonFiniteNumbersAnywhere) {
  // JSON has no NaN or infinity literal; an overflowing literal is how one sneaks in.
  std::string text = validScene().dump();
  const auto at = text.find("\"radius\":1");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 10, "\"radius\":1e999");
  EXPECT_EQ(rejectionPath(text), "spheres[0].radius");

  std::string light = validScene().dump();
  const auto dir = light.find("[-1,-1,1]");
  ASSERT_NE(dir, std::string::npos);
  light.replace(dir, 9, "[-1,-1e999,1]");
  EXPECT_EQ(rejectionPath(light), "lightData.directionalLightDirection[1]");
}

TEST(SceneLoader, RejectsNonPositiveRadius) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][1]["radius"] = 0; }), "spheres[1].radius");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][0]["radius"] = -1; }), "spheres[0].radius");
}

// The message of a rejected scene, or "<accepted>".
std::string rejectionMessage(const std::function<void(Json&)>& edit) {
  Json j = validScene();
  edit(j);
  try {
    parseScene(j.dump(), "scenes/test.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "<accepted>";
}

TEST(SceneLoader, RejectsMagnitudesAboveTheLimit) {
  // 1e39 is finite as a double and infinite as the float the renderers use.
  EXPECT_EQ(rejectionMessage([](Json& j) { j["spheres"][1]["radius"] = 1e39; }),
            "scenes/test.json: spheres[1].radius: radius 1e+39 is outside [1e-06, 1e+06]");
  EXPECT_EQ(rejectionMessage([](Json& j) { j["spheres"][0]["position"] = {0, -1000001, 0}; }),
            "scenes/test.json: spheres[0].position[1]: -1000001 is outside [-1e+06, 1e+06]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["position"] = {2e6, 1, -6}; }), "camera.position[0]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["forward"] = {0, 0, 1e7}; }), "camera.forward[2]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["focusPoint"] = {0, 0, -1e300}; }), "camera.focusPoint[2]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["lightData"]["directionalLightDirection"] = {-1e30, -1, 1}; }),
            "lightData.directionalLightDirection[0]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["orbitVelocity"] = -1e300; }), "camera.orbitVelocity");
}

TEST(SceneLoader, RejectsLengthsBelowTheLimit) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][1]["radius"] = 9e-7; }), "spheres[1].radius");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][1]["radius"] = 1e-320; }), "spheres[1].radius");
  // A direction this short has no reliable direction; one of 1e-200 squares to 0.
  EXPECT_EQ(rejectionPath([](Json& j) { j["lightData"]["directionalLightDirection"] = {1e-200, -1e-200, 0}; }),
            "lightData.directionalLightDirection");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["forward"] = {0, 0, 1e-7}; }), "camera.forward");
  // An orbit about a focus point this near would round the camera onto it.
  EXPECT_EQ(rejectionPath([](Json& j) {
              j["camera"]["position"] = {1e6, 0, 0};
              j["camera"]["focusPoint"] = {1e6, 0, 1e-9};
            }),
            "camera.focusPoint");
}

TEST(SceneLoader, AcceptsTheExtremesInsideTheLimits) {
  Json j = validScene();
  j["spheres"][0]["radius"] = 1e6;
  j["spheres"][1]["radius"] = 1e-6;
  j["spheres"][1]["position"] = {1e6, -1e6, 1e6};
  j["camera"]["position"] = {-1e6, 0, -1e6};
  j["camera"]["forward"] = {1e-6, 0, 0};
  j["camera"]["focusPoint"] = {-1e6, 0, -1e6 + 2e-6};
  j["camera"]["orbitVelocity"] = -1e6;
  const Scene s = parse(j);
  EXPECT_FLOAT_EQ(s.spheres[0].radius, 1e6f);
  EXPECT_FLOAT_EQ(s.spheres[1].radius, 1e-6f);
  EXPECT_FLOAT_EQ(s.spheres[1].position.y, -1e6f);
  EXPECT_DOUBLE_EQ(s.camera.forward.x, 1.0);
}

TEST(SceneLoader, RejectsFovOutsideOpenInterval) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["fov"] = 0; }), "camera.fov");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["fov"] = 180; }), "camera.fov");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["fov"] = -30; }), "camera.fov");
}

TEST(SceneLoader, RejectsZeroLengthDirections) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["forward"] = {0, 0, 0}; }), "camera.forward");
  EXPECT_EQ(rejectionPath([](Json& j) { j["lightData"]["directionalLightDirection"] = {0, 0, 0}; }),
            "lightData.directionalLightDirection");
}

TEST(SceneLoader, RejectsCameraLookingStraightUpOrDown) {
  // Static camera: its forward is what it uses.
  EXPECT_EQ(rejectionPath([](Json& j) {
              j["camera"].erase("focusPoint");
              j["camera"].erase("orbitVelocity");
              j["camera"]["forward"] = {0, -1, 0};
            }),
            "camera.forward");
  // Orbiting camera: it looks at the focus point, straight down here, in every frame.
  EXPECT_EQ(rejectionPath([](Json& j) {
              j["camera"]["position"] = {0, 5, 0};
              j["camera"]["focusPoint"] = {0, 0, 0.0001};
            }),
            "camera.focusPoint");
  // Just inside the limit is fine.
  Json ok = validScene();
  ok["camera"].erase("focusPoint");
  ok["camera"].erase("orbitVelocity");
  ok["camera"]["forward"] = {0.02, 1, 0};
  EXPECT_NO_THROW(parse(ok));
}

TEST(SceneLoader, RejectsPositionEqualToFocusPoint) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["focusPoint"] = {0, 1, -6}; }), "camera.focusPoint");
}

TEST(SceneLoader, RejectsOrbitWithoutFocusPoint) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"].erase("focusPoint"); }), "camera.orbitVelocity");
}

TEST(SceneLoader, RejectsMaxDepthOutsideRange) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["maxDepth"] = 0; }), "render.maxDepth");
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["maxDepth"] = 65; }), "render.maxDepth");
  Json ok = validScene();
  ok["render"]["maxDepth"] = 64;
  EXPECT_EQ(parse(ok).render.maxDepth, 64);
}

TEST(SceneLoader, RejectsColorComponentsOutsideUnitInterval) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][1]["color"] = {0.5, 1.5, 0}; }), "spheres[1].color[1]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["lightData"]["directionalLightColor"] = {-0.1, 1, 1}; }),
            "lightData.directionalLightColor[0]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["lightData"]["ambientLightColor"] = {0, 0, 2}; }),
            "lightData.ambientLightColor[2]");
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["background"] = {0, 0, 1.01}; }), "render.background[2]");
}

TEST(SceneLoader, RejectsZeroSpheres) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"] = Json::array(); }), "spheres");
}

TEST(SceneLoader, RejectsUnknownKeysAtEveryLevel) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheress"] = Json::array(); }), "spheress");
  EXPECT_EQ(rejectionPath([](Json& j) { j["camera"]["fovy"] = 60; }), "camera.fovy");
  EXPECT_EQ(rejectionPath([](Json& j) { j["lightData"]["color"] = {1, 1, 1}; }), "lightData.color");
  EXPECT_EQ(rejectionPath([](Json& j) { j["spheres"][1]["radious"] = 1; }), "spheres[1].radious");
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["depth"] = 3; }), "render.depth");
}

TEST(SceneLoader, RejectsAKeyGivenTwice) {
  std::string text = validScene().dump();
  const auto at = text.find("\"fov\":60");
  ASSERT_NE(at, std::string::npos);
  text.insert(at, "\"fov\":50,");
  EXPECT_EQ(rejectionPath(text), "camera.fov");
  try {
    parseScene(text, "scenes/test.json");
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("duplicate key"), std::string::npos) << e.what();
  }
}

// The fast parser stops at the first broken rule; the text is then read
// again so that a syntax error anywhere still takes precedence, as it did
// when the whole text was parsed before any rule was checked.
TEST(SceneLoader, ASyntaxErrorAfterABrokenRuleIsReportedAsTheSyntaxError) {
  Json j = validScene();
  j["spheres"][0]["radius"] = -1;
  for (const std::string tail : {" {}", ",", "]"}) {
    try {
      parseScene(j.dump() + tail, "scenes/test.json");
      ADD_FAILURE() << "accepted a text ending in " << tail;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("malformed JSON at line 1"), std::string::npos) << e.what();
      EXPECT_EQ(e.jsonPath(), "");
    }
  }
}

// A file longer than one read() and large enough for the hash to run beside
// the parse: every sphere arrives, and the hash is the file's.
TEST(SceneLoader, LoadsALargeFileWithItsHash) {
  Json j = validScene();
  constexpr int kSpheres = 20000;  // about 1.5 MB of JSON
  for (int i = 0; i < kSpheres; ++i) {
    j["spheres"].push_back({{"position", {i % 100, i / 100, 0}}, {"radius", 0.25}, {"color", {0.5, 0.5, 0.5}}});
  }
  const auto path = std::filesystem::temp_directory_path() / ("rt-large-scene-" + std::to_string(::getpid()) + ".json");
  std::ofstream(path) << j.dump(1);
  const Scene s = loadScene(path);
  EXPECT_EQ(s.spheres.size(), kSpheres + 2u);
  EXPECT_FLOAT_EQ(s.spheres.back().position.y, static_cast<float>((kSpheres - 1) / 100));
  EXPECT_EQ(s.sha256, sha256HexOfFile(path));
  std::filesystem::remove(path);
}

TEST(SceneLoader, RejectsOutOfRangeRenderParameters) {
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["reflectivity"] = 1.5; }), "render.reflectivity");
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["shininess"] = -1; }), "render.shininess");
  EXPECT_EQ(rejectionPath([](Json& j) { j["render"]["specularStrength"] = -0.5; }), "render.specularStrength");
}

}  // namespace
}  // namespace rt
