#pragma once
#include <string_view>

namespace rt {

// What this binary was built from and with; stamped into every run's metadata.
struct BuildInfo {
  std::string_view version;
  std::string_view gitCommit;
  bool gitDirty;
  std::string_view buildType;
  std::string_view compiler;
  std::string_view compilerFlags;
  std::string_view libraryVersions;  // "name=version,name=version"
  std::string_view tracyClient;      // Tracy client version, empty when not built in
};

const BuildInfo& buildInfo();

}  // namespace rt
