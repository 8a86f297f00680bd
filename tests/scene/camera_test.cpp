#include "scene/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace rt {
namespace {

CameraSpec orbitingCamera() {
  CameraSpec c;
  c.position = {0.0, 1.0, -6.0};
  c.focusPoint = glm::dvec3(0.0, 0.0, 0.0);
  c.forward = glm::normalize(*c.focusPoint - c.position);
  c.fov = 60.0;
  c.orbitVelocity = 0.5;
  return c;
}

void expectNear(glm::vec3 a, glm::vec3 b, float tolerance = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Camera, CentrePixelLooksAlongForward) {
  const CameraFrame cam = cameraAtFrame(orbitingCamera(), 0);
  const glm::vec3 dir = glm::normalize(primaryRayDirection<float>(cam, {5, 3}, 2, 1));
  expectNear(dir, cam.forward);
}

TEST(Camera, CornerPixelsFollowTheFormula) {
  CameraSpec spec;
  spec.position = {0.0, 0.0, 0.0};
  spec.forward = {0.0, 0.0, 1.0};
  spec.fov = 90.0;  // tan(45 deg) = 1
  const CameraFrame cam = cameraAtFrame(spec, 0);
  expectNear(cam.right, {-1.0f, 0.0f, 0.0f});  // cross(forward, +Y)
  expectNear(cam.up, {0.0f, 1.0f, 0.0f});
  const Extent e{4, 2};
  // Top-left pixel centre: u = (2 * 0.5 / 4 - 1) * 1 * 2 = -1.5, v = (1 - 2 * 0.5 / 2) * 1 = 0.5
  expectNear(primaryRayDirection<float>(cam, e, 0, 0), {1.5f, 0.5f, 1.0f});
  // Bottom-right: u = (2 * 3.5 / 4 - 1) * 2 = 1.5, v = (1 - 2 * 1.5 / 2) = -0.5
  expectNear(primaryRayDirection<float>(cam, e, 3, 1), {-1.5f, -0.5f, 1.0f});
}

TEST(Camera, FrameZeroOfAnOrbitIsTheStartPosition) {
  const CameraFrame cam = cameraAtFrame(orbitingCamera(), 0);
  expectNear(cam.position, {0.0f, 1.0f, -6.0f});
}

TEST(Camera, OrbitRotatesRightHandedAboutY) {
  // A quarter turn: 0.5 rad/s * k / 60 = pi / 2.
  const long long k = std::llround(std::numbers::pi / 2.0 / 0.5 * 60.0);
  const CameraFrame cam = cameraAtFrame(orbitingCamera(), k);
  const double angle = 0.5 * static_cast<double>(k) / 60.0;
  // x' = cos a x + sin a z, z' = -sin a x + cos a z, with (x, z) = (0, -6)
  expectNear(cam.position,
             {static_cast<float>(-6.0 * std::sin(angle)), 1.0f, static_cast<float>(-6.0 * std::cos(angle))}, 1e-5f);
  EXPECT_NEAR(cam.position.x, -6.0f, 1e-2f);
  expectNear(cam.forward, glm::normalize(-cam.position), 1e-6f);
}

TEST(Camera, FrameDependsOnlyOnItsIndex) {
  const CameraSpec spec = orbitingCamera();
  const CameraFrame direct = cameraAtFrame(spec, 1234);
  for (long long k = 0; k < 1234; k += 97) (void)cameraAtFrame(spec, k);
  const CameraFrame again = cameraAtFrame(spec, 1234);
  EXPECT_EQ(direct.position, again.position);
  EXPECT_EQ(direct.forward, again.forward);
  EXPECT_NEAR(glm::length(direct.position), std::sqrt(37.0f), 1e-5f);  // orbit keeps the distance
  EXPECT_FLOAT_EQ(direct.position.y, 1.0f);                            // and the height
}

TEST(Camera, StaticCameraIgnoresTheFrameIndex) {
  CameraSpec spec = orbitingCamera();
  spec.orbitVelocity = 0.0;
  spec.forward = {0.0, 0.0, 1.0};
  const CameraFrame a = cameraAtFrame(spec, 0);
  const CameraFrame b = cameraAtFrame(spec, 500);
  EXPECT_EQ(a.position, b.position);
  expectNear(b.forward, {0.0f, 0.0f, 1.0f});
}

TEST(Camera, MaxCoordinateCoversTheOrbit) {
  CameraSpec camera;
  camera.position = {0.0, 0.0, -10.0};
  camera.focusPoint = glm::dvec3(5.0, 0.0, 0.0);
  camera.orbitVelocity = 1.0;
  // 5 + |(-5, 0, -10)|: the orbit's radius about a focus 5 from the origin.
  EXPECT_NEAR(cameraMaxCoordinate(camera), 5.0 + std::sqrt(125.0), 1e-4);
  camera.orbitVelocity = 0.0;
  EXPECT_EQ(cameraMaxCoordinate(camera), 10.0f);
}

}  // namespace
}  // namespace rt
