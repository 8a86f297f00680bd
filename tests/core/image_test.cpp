#include "core/image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace rt {
namespace {

Image gradient(Extent e) {
  Image image(e);
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x)
      image.row(y)[x] = {static_cast<std::uint8_t>(x * 7), static_cast<std::uint8_t>(y * 11), 128, 255};
  return image;
}

TEST(ImageCompare, IdenticalImagesAgreeWithInfinitePsnr) {
  const Image a = gradient({20, 10});
  const ImageAgreement r = compareImages(a, a);
  EXPECT_EQ(r.fractionWithinTolerance, 1.0);
  EXPECT_TRUE(std::isinf(r.psnrDb));
  EXPECT_TRUE(r.agrees());
}

TEST(ImageCompare, DifferenceOfTwoIsWithinToleranceThreeIsNot) {
  const Image a = gradient({10, 10});
  Image b = a;
  b.row(0)[0].g = static_cast<std::uint8_t>(a.at(0, 0).g + 2);
  EXPECT_EQ(compareImages(a, b).fractionWithinTolerance, 1.0);
  b.row(0)[0].g = static_cast<std::uint8_t>(a.at(0, 0).g + 3);
  EXPECT_DOUBLE_EQ(compareImages(a, b).fractionWithinTolerance, 0.99);
  EXPECT_EQ(compareImages(a, b).maxChannelDifference, 3);
}

TEST(ImageCompare, TooManyDifferingPixelsDisagree) {
  const Image a = gradient({100, 10});
  Image b = a;
  for (int x = 0; x < 6; ++x) b.row(0)[x].r = static_cast<std::uint8_t>(a.at(x, 0).r ^ 0x80);  // 0.6 % of pixels
  const ImageAgreement r = compareImages(a, b);
  EXPECT_LT(r.fractionWithinTolerance, 0.995);
  EXPECT_FALSE(r.agrees());
}

TEST(ImageCompare, LowPsnrDisagreesEvenWhenFewPixelsDiffer) {
  const Image a = gradient({100, 100});
  Image b = a;
  for (int x = 0; x < 40; ++x) b.row(5)[x] = {static_cast<std::uint8_t>(255 - a.at(x, 5).r), 0, 0, 255};
  const ImageAgreement r = compareImages(a, b);
  EXPECT_GE(r.fractionWithinTolerance, 0.995);
  EXPECT_LT(r.psnrDb, 40.0);
  EXPECT_FALSE(r.agrees());
}

// The rule at scale (docs/render-model.md section 8): `full` and `primary`
// (maxDepth 1) frames of one scene against their references.
struct FramesAtScale {
  Image full = gradient({100, 100});
  Image primary = gradient({100, 100});
  [[nodiscard]] AgreementBreakdown against(const FramesAtScale& reference, float reflectivity = 0.5f) const {
    return breakDownAgreement(full, reference.full, primary, reference.primary, reflectivity);
  }
};

// Every `step`-th pixel's red channel moved by `by` (down where up would pass 255), in `image`.
void shiftRed(Image& image, int step, int by) {
  const auto pixels = image.pixels();
  for (std::size_t i = 0; i < pixels.size(); i += static_cast<std::size_t>(step)) {
    const int r = pixels[i].r;
    pixels[i].r = static_cast<std::uint8_t>(r + by <= 255 ? r + by : r - by);
  }
}

TEST(AgreementAtScale, ReflectedRayFlipsPassWhereSection8sRuleFails) {
  const FramesAtScale reference;
  FramesAtScale got;
  shiftRed(got.full, 50, 25);  // 2 % of the pixels, 25/255, camera rays alike
  const AgreementBreakdown b = got.against(reference);
  EXPECT_FALSE(b.full.agrees());
  EXPECT_EQ(b.reflectedOnly.pixels, 200u);
  EXPECT_EQ(b.primaryRay.pixels, 0u);
  EXPECT_EQ(b.reflectedOnly.max, 25);
  EXPECT_EQ(b.reflectedOnly.bands[2], 200u);  // the 16-50 band
  EXPECT_TRUE(b.agreesAtScale());
  // With no reflection, reflected rays cannot differ: the same frames fail.
  EXPECT_FALSE(got.against(reference, 0.0f).agreesAtScale());
}

// The defects the section 8 tests inject (ImageCompare above): 0.6 % of the
// pixels 128/255 off, and 40 pixels inverted, in the camera rays (both
// frames) or in the reflections only (the full frame).
TEST(AgreementAtScale, CatchesTheDefectsSection8Catches) {
  const FramesAtScale reference;
  for (const bool inCameraRays : {true, false}) {
    FramesAtScale spread;
    FramesAtScale inverted;
    for (Image* image : {&spread.full, &spread.primary}) {
      if (image == &spread.full || inCameraRays) shiftRed(*image, 167, 128);
    }
    for (Image* image : {&inverted.full, &inverted.primary}) {
      if (image != &inverted.full && !inCameraRays) continue;
      for (int x = 0; x < 40; ++x) image->row(5)[x] = {static_cast<std::uint8_t>(255 - image->at(x, 5).r), 0, 0, 255};
    }
    EXPECT_FALSE(spread.against(reference).agreesAtScale()) << "camera rays " << inCameraRays;
    EXPECT_FALSE(inverted.against(reference).agreesAtScale()) << "camera rays " << inCameraRays;
  }
}

// A bounce that is slightly wrong everywhere (small differences in a third
// of the pixels, PSNR still above 40 dB) is not a flip: the share catches it.
TEST(AgreementAtScale, SmallDifferencesInManyReflectionsDisagree) {
  const FramesAtScale reference;
  FramesAtScale got;
  shiftRed(got.full, 3, 4);
  const AgreementBreakdown b = got.against(reference);
  EXPECT_GE(b.full.psnrDb, 40.0);
  EXPECT_FALSE(b.agreesAtScale());
}

// A few pixels far beyond what a reflected ray could change (2/255 + 255 x
// reflectivity) count against the 99.5 %.
TEST(AgreementAtScale, ReflectedDifferencesBeyondTheWeightedToleranceCount) {
  const FramesAtScale reference;
  FramesAtScale got;
  shiftRed(got.full, 150, 30);  // 0.67 % of the pixels
  EXPECT_TRUE(got.against(reference, 0.5f).agreesAtScale());
  EXPECT_EQ(got.against(reference, 0.5f).withinWeightedTolerance, 10000u);
  EXPECT_FALSE(got.against(reference, 0.1f).agreesAtScale());  // tolerance 2 + 25: all 0.67 % beyond it
}

TEST(ImageCompare, RejectsDifferentExtents) {
  EXPECT_THROW(compareImages(Image({2, 2}), Image({2, 3})), std::invalid_argument);
}

TEST(ImagePng, RoundTripsExactlyAndLeavesNoTemporary) {
  const auto dir = std::filesystem::temp_directory_path() / "rt_image_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / "gradient.png";
  const Image a = gradient({33, 17});
  writePng(a, path);
  const Image b = readPng(path);
  EXPECT_EQ(b.extent(), a.extent());
  EXPECT_TRUE(std::equal(a.pixels().begin(), a.pixels().end(), b.pixels().begin()));
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  }
  std::filesystem::remove_all(dir);
}

TEST(ImagePng, WriteIntoMissingDirectoryThrows) {
  EXPECT_THROW(writePng(gradient({2, 2}), "/nonexistent-dir/x.png"), std::runtime_error);
}

}  // namespace
}  // namespace rt
