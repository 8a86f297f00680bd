#include "app/run_config.h"

namespace rt {

std::optional<std::filesystem::path> metadataPathFor(const RunConfig& config) {
  if (config.metaPath) return config.metaPath;
  if (!config.csvPath) return std::nullopt;
  std::filesystem::path meta = *config.csvPath;
  meta.replace_extension(".meta.json");
  return meta;
}

}  // namespace rt
