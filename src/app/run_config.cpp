#include "app/run_config.h"

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

}  // namespace rt
