#include "app/run_config.h"

#include <sstream>

namespace rt {

std::optional<std::filesystem::path> metadataPathFor(const RunConfig& config) {
  if (config.metaPath) return config.metaPath;
  if (!config.csvPath) return std::nullopt;
  // --csv /dev/null (a device, a FIFO) discards the frames; a sidecar beside
  // it would land in /dev. Only --meta writes one then.
  std::error_code ec;
  const auto status = std::filesystem::status(*config.csvPath, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) return std::nullopt;
  std::filesystem::path meta = *config.csvPath;
  meta.replace_extension(".meta.json");
  return meta;
}

std::optional<std::string> bruteForceNotice(const RunConfig& config, std::size_t sphereCount) {
  if (config.options.accel != Accel::none || sphereCount < kBruteForceNoticeSpheres) return std::nullopt;
  const double cameraRays = double(config.extent.width) * double(config.extent.height);
  const double tests = cameraRays * double(sphereCount);
  std::ostringstream notice;
  notice.precision(2);
  notice << "brute force (--accel none) tests every ray against all " << sphereCount << " spheres: " << std::scientific
         << tests << " sphere tests a frame for the camera rays alone, more after bounces; "
         << "--accel bvh tests a few dozen spheres a ray and is far faster on a scene this size "
         << "(docs/render-model.md section 3)";
  return notice.str();
}

}  // namespace rt
