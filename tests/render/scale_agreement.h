#pragma once
// A 100,000-sphere scene checked against the double-precision reference
// under the rule at scale (docs/render-model.md section 8): every renderer
// renders frame 0 twice, in full and with maxDepth 1, and breakDownAgreement
// compares both with the reference's. The scene and the reference's frames
// are made once per test binary and size.
#include <map>
#include <utility>

#include "core/image.h"
#include "render/render_test_support.h"
#include "render/scalar/double_reference.h"
#include "render/scale_scene.h"

namespace rt::test {

inline constexpr std::uint32_t kScaleSpheres = 100'000;
// --accel bvh at the agreement tests' small size; brute force (--accel none)
// walks all 100,000 spheres per ray, so smaller.
inline constexpr Extent kScaleExtentBvh{96, 64};
inline constexpr Extent kScaleExtentBruteForce{16, 10};

struct ScaleFrames {
  Image full;
  Image primary;  // maxDepth 1
};

inline const Scene& scaleScene() {
  static const Scene scene = randomSceneAtScale(kScaleSpheres);
  return scene;
}

inline Scene withMaxDepth(Scene scene, int maxDepth) {
  scene.render.maxDepth = maxDepth;
  return scene;
}

inline RenderOptions scaleOptions() { return optionsForStage(Stage::optimized); }

inline const ScaleFrames& scaleReferenceFrames(Extent extent) {
  static std::map<std::pair<int, int>, ScaleFrames> frames;
  auto& f = frames[{extent.width, extent.height}];
  if (f.full.pixels().empty()) {
    const Scene primaryScene = withMaxDepth(scaleScene(), 1);
    const CameraFrame camera = cameraAtFrame(scaleScene().camera, 0);
    f.full = DoubleReference(scaleScene()).render(camera, extent, scaleOptions());
    f.primary = DoubleReference(primaryScene).render(camera, extent, scaleOptions());
  }
  return f;
}

// `renderer`'s frame 0 of `rendered` (the scale scene, or one a defect
// changed) with `accel`, broken down against the scale scene's reference.
inline AgreementBreakdown scaleAgreement(Renderer& renderer, Accel accel, const Scene& rendered = scaleScene()) {
  const Extent extent = accel == Accel::bvh ? kScaleExtentBvh : kScaleExtentBruteForce;
  RenderOptions options = scaleOptions();
  options.accel = accel;
  const Image full = renderFrame(renderer, rendered, extent, options, 0);
  const Image primary = renderFrame(renderer, withMaxDepth(rendered, 1), extent, options, 0);
  const ScaleFrames& want = scaleReferenceFrames(extent);
  return breakDownAgreement(full, want.full, primary, want.primary, scaleScene().render.reflectivity);
}

inline std::string describe(const AgreementBreakdown& b) {
  return "full: " + describe(b.full) + "; maxDepth 1: " + describe(b.primary) +
         "; differing pixels: " + std::to_string(b.primaryRay.pixels) + " from the camera ray (max " +
         std::to_string(b.primaryRay.max) + "), " + std::to_string(b.reflectedOnly.pixels) +
         " from reflected rays only (max " + std::to_string(b.reflectedOnly.max) + ")";
}

}  // namespace rt::test
