#pragma once
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <span>
#include <vector>

namespace rt {

struct Rgba8 {
  std::uint8_t r, g, b, a;
  friend bool operator==(const Rgba8&, const Rgba8&) = default;
};
static_assert(sizeof(Rgba8) == 4);

struct Extent {
  int width = 0;
  int height = 0;
  [[nodiscard]] std::size_t pixelCount() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  friend bool operator==(const Extent&, const Extent&) = default;
};

// An 8-bit RGBA image, row 0 at the top, rows tightly packed.
class Image {
 public:
  Image() = default;
  explicit Image(Extent extent) : extent_(extent), pixels_(extent.pixelCount()) {}

  [[nodiscard]] Extent extent() const { return extent_; }
  [[nodiscard]] std::span<Rgba8> pixels() { return pixels_; }
  [[nodiscard]] std::span<const Rgba8> pixels() const { return pixels_; }
  [[nodiscard]] std::span<Rgba8> row(int y) {
    return std::span(pixels_).subspan(static_cast<std::size_t>(y) * extent_.width, extent_.width);
  }
  [[nodiscard]] Rgba8 at(int x, int y) const { return pixels_[static_cast<std::size_t>(y) * extent_.width + x]; }

 private:
  Extent extent_;
  std::vector<Rgba8> pixels_;
};

// Writes a PNG through a temporary file and a rename; throws on failure.
void writePng(const Image& image, const std::filesystem::path& path);
// Reads an 8-bit PNG (any channel count is expanded to RGBA); throws on failure.
Image readPng(const std::filesystem::path& path);

// How closely two images agree (docs/render-model.md section 8).
struct ImageAgreement {
  static constexpr int kChannelTolerance = 2;  // in 1/255 steps
  double fractionWithinTolerance = 0.0;        // pixels whose every channel differs by <= 2/255
  double psnrDb = 0.0;                         // infinity for identical images
  int maxChannelDifference = 0;
  [[nodiscard]] bool agrees() const;  // >= 99.5 % within tolerance and >= 40 dB
};

ImageAgreement compareImages(const Image& a, const Image& b);

// Pixels whose largest channel difference exceeds 2/255, by size.
struct DifferenceSizes {
  static constexpr int kBandUpper[] = {5, 15, 50, 100, 255};  // bands 3-5, 6-15, 16-50, 51-100, 101-255
  std::size_t pixels = 0;
  std::size_t bands[std::size(kBandUpper)] = {};
  int max = 0;
  void add(int difference);
};

// Where a frame differs from its reference, told apart by the camera ray:
// the same pair rendered again with maxDepth 1 (camera rays only, no
// reflection). A pixel over 2/255 apart in the full frames whose maxDepth 1
// renders are also over 2/255 apart differs from its camera ray on (another
// sphere, hit against miss, or its shading); one whose maxDepth 1 renders
// agree differs only by what its reflected rays met. The rule at scale of
// docs/render-model.md section 8 is agreesAtScale().
struct AgreementBreakdown {
  ImageAgreement full;            // compareImages of the full frames
  ImageAgreement primary;         // compareImages of the maxDepth 1 frames
  DifferenceSizes primaryRay;     // differing pixels whose camera ray differs
  DifferenceSizes reflectedOnly;  // differing pixels whose camera ray agrees
  std::size_t pixelCount = 0;
  // Pixels within their tolerance: 2/255 where the camera ray differs,
  // 2/255 + 255 x reflectivity where only reflected rays change the pixel.
  std::size_t withinWeightedTolerance = 0;
  float reflectivity = 0.0f;  // the scene's, which weighs reflected-ray differences

  // The maxDepth 1 frames agree under section 8's rule, the full frames
  // have PSNR >= 40 dB, at most 10 % x reflectivity of the pixels differ
  // only by reflected rays, and >= 99.5 % are within their tolerance.
  [[nodiscard]] bool agreesAtScale() const;
};

AgreementBreakdown breakDownAgreement(const Image& full, const Image& fullReference, const Image& primary,
                                      const Image& primaryReference, float reflectivity);

}  // namespace rt
