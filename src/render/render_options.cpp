#include "render/render_options.h"

namespace rt {

std::string EarlyExitSet::toString() const {
  std::string joined;
  for (std::size_t i = 0; i < schema::kEarlyExitNames.size(); ++i) {
    if (!has(static_cast<EarlyExit>(i))) continue;
    if (!joined.empty()) joined += '+';
    joined += schema::kEarlyExitNames[i];
  }
  return joined.empty() ? "none" : joined;
}

RenderOptions optionsForStage(Stage stage) {
  const auto& definition = schema::kStageDefinitions[static_cast<std::size_t>(stage)];
  return {definition.algorithm, EarlyExitSet(definition.earlyExitMask)};
}

}  // namespace rt
