// The extremes inside the scene limits (docs/render-model.md section 1,
// Limits; section 4 on the clamped highlight and the normal facing the
// ray): no NaN or infinity reaches a pixel. The renderers
// quantise to 8 bits, where a NaN becomes an arbitrary byte, so the scalar
// model is checked before quantisation (every colour finite), and every
// other renderer's picture against the sequential renderer's.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "render/accel/bvh.h"
#include "render/cpu_renderers.h"
#include "render/extreme_scenes.h"
#include "render/render_test_support.h"
#include "render/scalar/double_reference.h"
#include "render/scalar/scalar_model.h"

namespace rt {
namespace {

using test::kExtremeExtent;

// Frame 0 (the file's camera) and an orbited one.
constexpr long long kFrames[] = {0, 30};

bool finite(const kernel::Vec3<float>& c) { return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z); }

kernel::Ray<float> primaryRay(const CameraFrame& camera, int x, int y) {
  return kernel::primaryRay<float>(camera, kExtremeExtent, x, y);
}

// The float colour of every pixel, before clamping and quantisation, with
// both algorithms and with and without the bounce exit.
TEST(ScalarModel, ExtremeScenesGiveFiniteColoursBeforeQuantisation) {
  std::array<kernel::PathSegment<float>, kMaxDepthLimit> segments{};
  for (const auto& [name, scene] : test::extremeScenes()) {
    // The BVH finds the nearest hit brute force finds (tested in
    // tests/render/accel/), in a fraction of the time on 100,000 spheres.
    const Bvh bvh = buildBvh(scene.spheres);
    const auto in = kernel::ShadingInputs<float>::from(scene, &bvh);
    for (const long long frame : kFrames) {
      if (frame != 0 && !scene.camera.orbits()) continue;  // the same picture
      const CameraFrame camera = cameraAtFrame(scene.camera, frame);
      int nonFinite = 0;
      for (int y = 0; y < kExtremeExtent.height; ++y) {
        for (int x = 0; x < kExtremeExtent.width; ++x) {
          const kernel::Ray<float> ray = primaryRay(camera, x, y);
          nonFinite += finite(kernel::traceSinglePass<float, true, Accel::bvh>(in, ray)) ? 0 : 1;
          nonFinite += finite(kernel::traceSinglePass<float, false, Accel::bvh>(in, ray)) ? 0 : 1;
          nonFinite += finite(kernel::traceTwoPass<float, false, Accel::bvh>(in, ray, segments)) ? 0 : 1;
        }
      }
      EXPECT_EQ(nonFinite, 0) << name << " frame " << frame;
    }
  }
}

// The radius-1e-6 scene really is hit: the middle pixel's ray meets the
// smallest sphere head on, so its normal and shading are exercised.
TEST(ScalarModel, TheSmallestSphereIsHitByTheMiddlePixel) {
  {
    const Scene scene = test::extremeScene("radius-1e-6");
    const CameraFrame camera = cameraAtFrame(scene.camera, 0);
    const auto hit = kernel::nearestHitOfAll(primaryRay(camera, kExtremeExtent.width / 2, kExtremeExtent.height / 2),
                                             std::span<const Sphere>(scene.spheres));
    EXPECT_EQ(hit.sphere, 0);
    EXPECT_TRUE(finite(hit.normal));
  }
}

// Every CPU renderer of this build against the sequential renderer, whose
// colours the test above found finite: a NaN or infinity would show as
// pixels that disagree. Not against double precision: at 1e6 a float's step
// is 1/16 and the pictures part by design (97 % of the pixels agree on
// positions-1e6). Not on sky-radius-1e6 either: there the bounce offset of
// 1e-4 is below the float spacing of the sky's surface, rays re-hit the sky
// at t = 1/16, and each renderer's rounding sends them elsewhere (40 to 60 %
// agree); its colours are checked finite above.
//
// A renderer whose ray query is not ours (the schema's own_accel: Embree)
// rounds with its own arithmetic (src/render/embree/README.md, difference 3).
// On 100000-small, spheres a few pixels wide whose reflections graze many
// silhouettes, float rounding alone parts pictures by more than section 8
// allows: the sequential renderer itself agrees with the double-precision
// model on 99.27 % of the pixels at 33x25 (98.9 % at 330x250), and Embree
// with ours on 5 pixels fewer than the rule's 99.5 % on an AVX2 CPU (it did
// pass on AVX-512). Such a renderer is judged there against the
// double-precision model instead: no further from it than the sequential
// renderer is, give or take the rule's own 0.5 % of the pixels, and at least
// 40 dB. A NaN or an infinity would still show, as whole wrong pixels.
bool roundsOnItsOwn(RendererKind kind) {
  return schema::kRendererDefinitions[static_cast<std::size_t>(kind)].ownAccel.has_value();
}
constexpr double kRuleSlack = 0.005;

TEST(EveryCpuRenderer, ExtremeScenesAgreeWithTheSequentialRenderer) {
  for (const auto& [name, scene] : test::extremeScenes()) {
    if (name == "sky-radius-1e6") continue;
    const bool rounding = name == "100000-small";
    for (const Stage stage : {Stage::original, Stage::optimized}) {
      RenderOptions o = optionsForStage(stage);
      if (scene.spheres.size() > 1000) o.accel = Accel::bvh;  // the same hits, in a test's time
      SequentialRenderer sequential;
      const Image want = test::renderFrame(sequential, scene, kExtremeExtent, o, kFrames[1]);
      const Image exact =
          rounding ? renderDoubleReference(scene, cameraAtFrame(scene.camera, kFrames[1]), kExtremeExtent, o) : Image{};
      for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) {
        const auto kind = static_cast<RendererKind>(i);
        if (!cpuRendererBuilt(kind) || kind == RendererKind::sequential) continue;
        const auto renderer = makeCpuRenderer(kind, ParallelSettings{.threads = 2});
        const Image got = test::renderFrame(*renderer, scene, kExtremeExtent, o, kFrames[1]);
        const std::string what = name + " " + std::string(nameOf(kind)) + " " + std::string(nameOf(stage));
        if (rounding && roundsOnItsOwn(kind)) {
          const ImageAgreement ours = compareImages(want, exact);
          const ImageAgreement theirs = compareImages(got, exact);
          EXPECT_GE(theirs.fractionWithinTolerance, ours.fractionWithinTolerance - kRuleSlack)
              << what << " against double: " << test::describe(theirs) << "; sequential: " << test::describe(ours);
          EXPECT_GE(theirs.psnrDb, 40.0) << what << " against double: " << test::describe(theirs);
        } else {
          const ImageAgreement a = compareImages(got, want);
          EXPECT_TRUE(a.agrees()) << what << ": " << test::describe(a);
        }
      }
    }
  }
}

}  // namespace
}  // namespace rt
