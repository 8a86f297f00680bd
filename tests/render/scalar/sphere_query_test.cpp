#include "render/scalar/sphere_query.h"

#include <gtest/gtest.h>

#include <vector>

namespace rt::kernel {
namespace {

Ray<float> rayAlongZ(float z0) { return {{0.0f, 0.0f, z0}, {0.0f, 0.0f, 1.0f}}; }
Sphere sphereAt(glm::vec3 c, float r) { return {c, r, glm::vec3(1.0f)}; }
RaycastHit<float> nearestAlongZ(const std::vector<Sphere>& spheres) {
  return nearestHitOfAll(rayAlongZ(0), std::span<const Sphere>(spheres));
}

// A ray from the origin along +z against one sphere: where it hits, and the
// normal there, which faces the ray (docs/render-model.md section 4): outward
// where the ray enters, inward where it leaves.
struct SingleSphereCase {
  const char* what;
  Sphere sphere;
  float distance;
  glm::vec3 normal;
};

TEST(Intersection, SingleSphereHitsWhereTheModelSays) {
  const SingleSphereCase cases[] = {
      {"from outside: the near side", sphereAt({0, 0, 5}, 1), 4.0f, {0, 0, -1}},
      {"from inside: the far side, normal turned inward", sphereAt({0, 0, 0}, 2), 2.0f, {0, 0, -1}},
      {"tangent: the touching point", sphereAt({1, 0, 5}, 1), 5.0f, {-1, 0, 0}},
  };
  for (const SingleSphereCase& c : cases) {
    const RaycastHit<float> hit = nearestAlongZ({c.sphere});
    ASSERT_TRUE(hit.hit()) << c.what;
    EXPECT_FLOAT_EQ(hit.distance, c.distance) << c.what;
    EXPECT_NEAR(glm::distance(hit.normal, c.normal), 0.0f, 1e-6f) << c.what;
  }
}

TEST(Intersection, JustMissingRayMisses) {
  const std::vector<Sphere> s{sphereAt({1.001f, 0, 5}, 1)};
  EXPECT_FALSE(nearestHitOfAll(rayAlongZ(0), std::span<const Sphere>(s)).hit());
}

TEST(Intersection, SphereBehindTheOriginIsNotHit) {
  const std::vector<Sphere> s{sphereAt({0, 0, -5}, 1)};
  EXPECT_FALSE(nearestHitOfAll(rayAlongZ(0), std::span<const Sphere>(s)).hit());
  EXPECT_LE(intersectSphere(rayAlongZ(0), s[0]), kEpsilon<float>);
}

TEST(Intersection, HitCloserThanEpsilonIsSkippedForTheFarSide) {
  // A reflected ray starts on the surface: the near root is ~0 and must not count.
  const RaycastHit<float> hit = nearestAlongZ({sphereAt({0, 0, 1}, 1)});
  ASSERT_TRUE(hit.hit());
  EXPECT_FLOAT_EQ(hit.distance, 2.0f);
}

TEST(Intersection, NearestOfSeveralWins) {
  const RaycastHit<float> hit =
      nearestAlongZ({sphereAt({0, 0, 10}, 1), sphereAt({0, 0, 4}, 1), sphereAt({0, 0, 7}, 1)});
  EXPECT_EQ(hit.sphere, 1);
  EXPECT_FLOAT_EQ(hit.distance, 3.0f);
}

TEST(Intersection, ExactTieGoesToTheLowerIndex) {
  Sphere a = sphereAt({0, 0, 5}, 1);
  Sphere b = a;
  b.color = glm::vec3(0.5f);
  const std::vector<Sphere> s{sphereAt({0, 0, 50}, 1), a, b};
  EXPECT_EQ(nearestHitOfAll(rayAlongZ(0), std::span<const Sphere>(s)).sphere, 1);
}

TEST(Intersection, SmallFarSphereDoesNotCancel) {
  // The textbook discriminant loses this sphere in float; docs/render-model.md section 3's form keeps it.
  const RaycastHit<float> hit = nearestAlongZ({sphereAt({0.0f, 0.0009f, 3000.0f}, 0.001f)});
  ASSERT_TRUE(hit.hit());
  EXPECT_NEAR(hit.distance, 3000.0f - std::sqrt(0.001f * 0.001f - 0.0009f * 0.0009f), 1e-2f);
}

}  // namespace
}  // namespace rt::kernel
