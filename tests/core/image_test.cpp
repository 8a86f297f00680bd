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
