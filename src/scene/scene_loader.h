#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace rt {

// A rejected scene file: names the file and the JSON path of the culprit.
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& file, std::string jsonPath, const std::string& reason);
  [[nodiscard]] const std::string& jsonPath() const { return jsonPath_; }

 private:
  std::string jsonPath_;
};

Scene loadScene(const std::filesystem::path& path);
// `sourceName` is used in errors and as the scene name's source.
Scene parseScene(std::string_view jsonText, const std::string& sourceName);

}  // namespace rt
