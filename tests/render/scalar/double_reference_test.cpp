// The double-precision reference walks the BVH with its own pad
// (render/scalar/double_traversal_pad.h): it must give brute force's image
// byte for byte, on every committed scene, the adversarial and extreme
// scenes (random10000 and 100000-small have deep trees), for both
// algorithms with and without the bounce exit.
#include "render/scalar/double_reference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ranges>
#include <span>
#include <string>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "render/extreme_scenes.h"
#include "render/scalar/double_traversal_pad.h"
#include "render/scalar/sphere_query.h"
#include "test_support.h"

namespace rt {
namespace {

// Brute force costs pixels x spheres x depth: the extent shrinks as the
// scene grows, so each scene costs about the same (seconds under ASan).
Extent extentFor(const Scene& scene) {
  constexpr double kSphereRays = 5e5;
  const double pixels =
      std::clamp(kSphereRays / static_cast<double>(std::max<std::size_t>(scene.spheres.size(), 1)), 48.0, 96.0 * 64.0);
  const int height = std::max(8, static_cast<int>(std::sqrt(pixels / 1.5)));
  return {static_cast<int>(1.5 * height) | 1, height | 1};  // odd: the centre pixel's ray is the forward one
}

std::vector<test::NamedScene> scenesToCheck() {
  std::vector<test::NamedScene> scenes;
  for (const char* name : {"default", "random20", "random100", "random1000", "random10000"}) {
    scenes.push_back({name, test::loadNamedScene(name)});
  }
  for (test::NamedScene& s : test::adversarialScenes()) scenes.push_back(std::move(s));
  for (test::NamedScene& s : test::extremeScenes()) scenes.push_back(std::move(s));
  return scenes;
}

// Frames 0 and 30 where the camera orbits (frame 0 alone where it does not).
constexpr std::array<long long, 2> kFrameList{0, 30};
constexpr std::span<const long long> kFrames(kFrameList);

// Both algorithms, each with and without the bounce exit (the scalar model's
// only early exit); above 1000 spheres two of the four (single-pass with the
// exit, two-pass without), which still run each algorithm and each exit.
std::vector<RenderOptions> variants(std::size_t spheres) {
  const EarlyExitSet bounce = optionsForStage(Stage::single_pass).earlyExits;
  if (spheres > 1000) return {{Algorithm::single_pass, bounce}, {Algorithm::two_pass, EarlyExitSet{}}};
  std::vector<RenderOptions> all;
  for (Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
    for (EarlyExitSet exits : {EarlyExitSet{}, bounce}) all.push_back({algorithm, exits});
  }
  return all;
}

TEST(DoubleReference, BvhGivesBruteForcesImageByteForByte) {
  for (const test::NamedScene& named : scenesToCheck()) {
    const DoubleReference bvh(named.scene, ReferenceSearch::bvh);
    const DoubleReference bruteForce(named.scene, ReferenceSearch::brute_force);
    const Extent extent = extentFor(named.scene);
    for (const RenderOptions& options : variants(named.scene.spheres.size())) {
      for (long long frame : named.scene.camera.orbits() ? kFrames : kFrames.first(1)) {
        const CameraFrame camera = cameraAtFrame(named.scene.camera, frame);
        const Image want = bruteForce.render(camera, extent, options);
        const Image got = bvh.render(camera, extent, options);
        const auto differing =
            std::ranges::count_if(std::views::iota(std::size_t{0}, want.pixels().size()),
                                  [&](std::size_t i) { return got.pixels()[i] != want.pixels()[i]; });
        EXPECT_EQ(differing, 0) << named.name << " " << nameOf(options.algorithm) << " bounce exit "
                                << options.earlyExits.has(EarlyExit::bounce) << " frame " << frame << " at "
                                << extent.width << "x" << extent.height;
      }
    }
  }
}

// The free function is the BVH reference, whatever --accel says.
TEST(DoubleReference, IgnoresAccelOption) {
  const Scene scene = test::loadNamedScene("random100");
  RenderOptions options = optionsForStage(Stage::optimized);
  const CameraFrame camera = cameraAtFrame(scene.camera, 0);
  const Image a = renderDoubleReference(scene, camera, {33, 21}, options);
  options.accel = options.accel == Accel::bvh ? Accel::none : Accel::bvh;
  const Image b = renderDoubleReference(scene, camera, {33, 21}, options);
  EXPECT_TRUE(std::ranges::equal(a.pixels(), b.pixels()));
}

// A box bound is position + radius rounded to float, which may land inside
// the exact sphere: a ray in that gap, parallel to the bound, hits the
// sphere in double and misses the unpadded box. Spheres whose +x bound
// rounds down, each with such a ray: the BVH must find brute force's hit.
TEST(DoubleTraversalPad, FindsHitsInTheGapBetweenTheFloatBoxAndTheSphere) {
  std::vector<Sphere> spheres;
  std::vector<kernel::Ray<double>> rays;
  for (std::uint32_t i = 0; spheres.size() < 200; ++i) {
    const Sphere s{{1000.0f + 500.0f * test::unitNoise(i, 1), 0.0f, 0.0f}, 0.5f + test::unitNoise(i, 2), {1, 1, 1}};
    const double exact = static_cast<double>(s.position.x) + static_cast<double>(s.radius);
    const auto rounded = static_cast<double>(s.position.x + s.radius);
    if (!(rounded < exact)) continue;
    spheres.push_back(s);
    rays.push_back({{0.5 * (rounded + exact), 0.0, -100.0}, {0.0, 0.0, 1.0}});
  }
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const std::span<const Sphere> one(&spheres[i], 1);
    const Bvh bvh = buildBvh(one);
    const kernel::RaycastHit<double> want = kernel::nearestHitOfAll(rays[i], one);
    ASSERT_TRUE(want.hit()) << "sphere " << i << ": the ray must graze it";
    EXPECT_EQ(kernel::nearestHitInBvh(rays[i], one, bvh).sphere, want.sphere) << "sphere " << i;
  }
}

TEST(DoubleTraversalPad, CoversTheFloatBoxesAndIsBelowTheFloatPad) {
  const Scene scene = test::loadNamedScene("random1000");
  const Bvh bvh = buildBvh(scene.spheres);
  const double pad = doubleTraversalPad(bvh, 50.0);
  // A float bound is within half an ulp of the exact one: the pad must exceed that.
  EXPECT_GT(pad, std::ldexp(static_cast<double>(bvh.maxCoordinate), -24));
  EXPECT_LT(pad, static_cast<double>(traversalPad(bvh, 50.0f)));
}

}  // namespace
}  // namespace rt
