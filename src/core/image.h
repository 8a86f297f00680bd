#pragma once
#include <cstdint>
#include <filesystem>
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
  double fractionWithinTolerance = 0.0;  // pixels whose every channel differs by <= 2/255
  double psnrDb = 0.0;                   // infinity for identical images
  int maxChannelDifference = 0;
  [[nodiscard]] bool agrees() const;  // >= 99.5 % within tolerance and >= 40 dB
};

ImageAgreement compareImages(const Image& a, const Image& b);

}  // namespace rt
