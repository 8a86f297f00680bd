// The gap between a sphere's float box and where the float test still
// reports a hit, on a scene of mixed sizes (docs/render-model.md section 3,
// "The bound is local"): the double reference's gap test
// (tests/render/scalar/double_reference_test.cpp) for the float walks. A
// ground of radius 1000 whose top is y = 0: a ray along x at a height y
// computes o - c as y + 1000 in float, which is 1000 up to y = 2^-15, so the
// float test hits the ground up to 2^-15 above its exact top and its float
// box. A box must reach that high to keep the hit: the ray's share of the
// pad does not (the ray starts near the origin), the ground's own pad does.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "render/accel/accel_scenes.h"
#include "render/accel/bvh.h"
#include "render/accel/grid_walk.h"
#include "render/accel/sphere_grid.h"
#include "render/scalar/sphere_query.h"

namespace rt {
namespace {

// The ground, eight spheres of radius 0.2 on a ring of radius 3 about its
// top (none on the x axis), and one of radius 1.
std::vector<Sphere> mixedSizes() {
  std::vector<Sphere> spheres{{{0, -1000, 0}, 1000, {0.5f, 0.5f, 0.5f}}};
  for (int k = 0; k < 8; ++k) {
    const float angle = 0.3927f + 0.7854f * static_cast<float>(k);  // 22.5 + 45 k degrees
    spheres.push_back({{3 * std::cos(angle), 0.2f, 3 * std::sin(angle)}, 0.2f, {1, 0, 0}});
  }
  spheres.push_back({{5, 1, 5}, 1, {0, 0, 1}});
  return spheres;
}

// Along +x over the ground's top at height y, from just before it.
kernel::Ray<float> overTheTop(float y) { return {{-0.01f, y, 0.0f}, {1.0f, 0.0f, 0.0f}}; }

// The largest float v in [low, high] with found(v), where found is false at
// high and true from some v on down to low (bisection on the bits of
// non-negative floats, whose order is their values').
template <typename Found>
float lastFound(float low, float high, Found found) {
  std::uint32_t lo = std::bit_cast<std::uint32_t>(low), hi = std::bit_cast<std::uint32_t>(high);
  while (hi - lo > 1) {
    const std::uint32_t mid = lo + (hi - lo) / 2;
    (found(std::bit_cast<float>(mid)) ? lo : hi) = mid;
  }
  return std::bit_cast<float>(lo);
}

std::size_t leafOf(const Bvh& bvh, std::uint32_t sphere) {
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode& n = bvh.nodes[i];
    if (n.leaf() && bvh.order[n.first] == sphere) return i;
  }
  throw std::logic_error("no leaf holds the sphere");
}

TEST(TraversalGap, AHitAboveTheGroundsFloatBoxNeedsTheGroundsOwnPad) {
  const std::vector<Sphere> spheres = mixedSizes();
  const Sphere& ground = spheres[0];
  const auto hitsGround = [&](float y) {
    return kernel::intersectSphere(overTheTop(y), ground) > kernel::kEpsilon<float>;
  };
  ASSERT_TRUE(hitsGround(0.0f));
  const float gap = lastFound(0.0f, 1e-3f, hitsGround);
  EXPECT_EQ(gap, 0x1p-15f) << "half an ulp of 1000";
  ASSERT_EQ(ground.position.y + ground.radius, 0.0f) << "the float box's top";
  const kernel::Ray<float> ray = overTheTop(gap);
  const auto want = kernel::nearestHitOfAll(ray, std::span<const Sphere>(spheres));
  ASSERT_EQ(want.sphere, 0) << "the ground, 2^-15 above its float box";

  // Local padding: one sphere per leaf, the ground's box widened by its own pad.
  const Bvh local = buildBvh(spheres, kSingleSphereLeaves, BoxPadding::local);
  ASSERT_EQ(local.padding, BoxPadding::local);
  EXPECT_EQ(kernel::nearestHitInBvh(ray, std::span<const Sphere>(spheres), local).sphere, 0);
  const std::size_t groundLeaf = leafOf(local, 0);
  const auto foundWithTop = [&](float top) {
    Bvh changed = local;
    changed.nodes[groundLeaf].hi.y = top;
    return kernel::nearestHitInBvh(ray, std::span<const Sphere>(spheres), changed).sphere == 0;
  };
  // The lowest top that keeps the hit lies above the float box (the ray's
  // share of the pad alone loses it): the gap less the walk's pad for this
  // ray, within the ground's own pad.
  const float builtTop = local.nodes[groundLeaf].hi.y;
  ASSERT_TRUE(foundWithTop(builtTop));
  EXPECT_FALSE(foundWithTop(0.0f)) << "the float box, widened by the ray's share only";
  const float lastLost = lastFound(0.0f, builtTop, [&](float top) { return !foundWithTop(top); });
  const float lowestTop = std::nextafter(lastLost, builtTop);
  EXPECT_TRUE(foundWithTop(lowestTop));
  EXPECT_FALSE(foundWithTop(std::nextafter(lowestTop, -1.0f))) << "one float step short";
  const float rayPad = traversalPad(local, 0.01f);
  EXPECT_LE(lowestTop, gap - 0.5f * rayPad);
  EXPECT_GE(lowestTop, gap - 1.5f * rayPad);
  // The bound is local: the small spheres' boxes carry a few hundredths,
  // the ground's its own pad of several units.
  EXPECT_GT(builtTop, 1.0f);
  for (std::uint32_t i = 1; i < spheres.size(); ++i) {
    const BvhNode& leaf = local.nodes[leafOf(local, i)];
    EXPECT_LT(double(leaf.hi.y) - (double(spheres[i].position.y) + spheres[i].radius), 0.1) << i;
  }

  // The grid keeps the ground apart and tests it before the walk.
  const SphereGrid grid = buildSphereGrid(spheres, sphereGridMargins(spheres, originBound(local.maxCoordinate, 1.0f)));
  ASSERT_EQ(grid.apartCount, 1u);
  EXPECT_EQ(test::nearestHitInGrid(ray, spheres, grid).sphere, 0);
}

}  // namespace
}  // namespace rt
