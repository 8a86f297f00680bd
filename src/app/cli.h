#pragma once
#include <string>
#include <variant>

#include "app/run_config.h"

namespace rt {

// What the command line asks for: a run, or an answer printed and an exit code.
struct CliExit {
  int code = 0;
  std::string output;  // for stdout (help, version)
  std::string error;   // for stderr
};

// A failure while running (a GPU error, validation errors, any other error).
inline constexpr int kExitRuntimeError = 1;
inline constexpr int kExitBadInput = 2;
// No Vulkan loader or device where the run needs one (--gpu, --present upload, --list-devices).
inline constexpr int kExitNoDevice = 3;

std::variant<RunConfig, CliExit> parseCommandLine(int argc, const char* const* argv);

// "--version" text: version, commit, build type, compiler.
std::string versionText();

}  // namespace rt
