#include "core/image.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/atomic_file.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
// stb_image's PNG reader sets the 16-bit transparent colour (tc16) from a
// tRNS chunk and reads it only under the same conditions (has_trans, depth
// 16); after inlining, GCC 14 cannot see that and warns it may be used
// uninitialized. The library is not ours to change.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace rt {
namespace {
// docs/render-model.md section 8: the agreement thresholds between two renderers.
constexpr int kChannelTolerance = ImageAgreement::kChannelTolerance;
constexpr double kMinFractionWithinTolerance = 0.995;
constexpr double kMinPsnrDb = 40.0;
// The rule at scale: pixels only reflected rays change, at most this share
// times the reflectivity (docs/render-model.md section 8).
constexpr double kMaxReflectedOnlyPerReflectivity = 0.10;
}  // namespace

void writePng(const Image& image, const std::filesystem::path& path) {
  // Encoded in memory, then written like every other output: stb's own file
  // writer ignores fwrite's errors, so a full disk left a truncated PNG.
  const Extent e = image.extent();
  std::string encoded;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  const int ok = stbi_write_png_to_func(append, &encoded, e.width, e.height, 4, image.pixels().data(), e.width * 4);
  if (ok == 0) throw std::runtime_error(path.string() + ": cannot encode PNG");
  writeFileAtomically(path, encoded);
}

Image readPng(const std::filesystem::path& path) {
  int w = 0, h = 0, channels = 0;
  std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> data(stbi_load(path.c_str(), &w, &h, &channels, 4),
                                                            &stbi_image_free);
  if (!data) {
    throw std::runtime_error(path.string() + ": cannot read PNG: " + stbi_failure_reason());
  }
  Image image(Extent{w, h});
  std::copy_n(reinterpret_cast<const Rgba8*>(data.get()), image.pixels().size(), image.pixels().begin());
  return image;
}

bool ImageAgreement::agrees() const {
  return fractionWithinTolerance >= kMinFractionWithinTolerance && psnrDb >= kMinPsnrDb;
}

namespace {
int largestChannelDifference(Rgba8 a, Rgba8 b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}
}  // namespace

ImageAgreement compareImages(const Image& a, const Image& b) {
  if (a.extent() != b.extent()) throw std::invalid_argument("compareImages: extents differ");
  const auto pa = a.pixels();
  const auto pb = b.pixels();
  std::size_t within = 0;
  double squaredError = 0.0;
  int maxDiff = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    // Alpha is always opaque; only colour channels are compared.
    const int d[3] = {std::abs(pa[i].r - pb[i].r), std::abs(pa[i].g - pb[i].g), std::abs(pa[i].b - pb[i].b)};
    const int m = std::max({d[0], d[1], d[2]});
    maxDiff = std::max(maxDiff, m);
    within += m <= kChannelTolerance ? 1 : 0;
    for (int c : d) squaredError += static_cast<double>(c) * c;
  }
  ImageAgreement result;
  result.maxChannelDifference = maxDiff;
  result.fractionWithinTolerance = pa.empty() ? 1.0 : static_cast<double>(within) / static_cast<double>(pa.size());
  const double mse = pa.empty() ? 0.0 : squaredError / (3.0 * static_cast<double>(pa.size()));
  result.psnrDb = mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
  return result;
}

void DifferenceSizes::add(int difference) {
  ++pixels;
  max = std::max(max, difference);
  std::size_t band = 0;
  while (difference > kBandUpper[band]) ++band;
  ++bands[band];
}

bool AgreementBreakdown::agreesAtScale() const {
  const auto n = static_cast<double>(pixelCount);
  return primary.agrees() && full.psnrDb >= kMinPsnrDb &&
         static_cast<double>(reflectedOnly.pixels) <= kMaxReflectedOnlyPerReflectivity * reflectivity * n &&
         static_cast<double>(withinWeightedTolerance) >= kMinFractionWithinTolerance * n;
}

AgreementBreakdown breakDownAgreement(const Image& full, const Image& fullReference, const Image& primary,
                                      const Image& primaryReference, float reflectivity) {
  AgreementBreakdown result;
  result.reflectivity = reflectivity;
  const int reflectedTolerance = kChannelTolerance + static_cast<int>(255.0f * reflectivity);
  result.full = compareImages(full, fullReference);
  result.primary = compareImages(primary, primaryReference);
  if (primary.extent() != full.extent()) throw std::invalid_argument("breakDownAgreement: extents differ");
  result.pixelCount = full.pixels().size();
  for (std::size_t i = 0; i < result.pixelCount; ++i) {
    const int d = largestChannelDifference(full.pixels()[i], fullReference.pixels()[i]);
    if (d <= kChannelTolerance) {
      ++result.withinWeightedTolerance;
      continue;
    }
    const bool cameraRayDiffers =
        largestChannelDifference(primary.pixels()[i], primaryReference.pixels()[i]) > kChannelTolerance;
    (cameraRayDiffers ? result.primaryRay : result.reflectedOnly).add(d);
    if (!cameraRayDiffers && d <= reflectedTolerance) ++result.withinWeightedTolerance;
  }
  return result;
}

}  // namespace rt
