#pragma once
// Parses a command line as `raytracer ARGS...` for the CLI tests.
#include <gtest/gtest.h>

#include <initializer_list>
#include <variant>
#include <vector>

#include "app/cli.h"

namespace rt::test {

inline std::variant<RunConfig, CliExit> parse(std::initializer_list<const char*> args) {
  std::vector<const char*> argv{"raytracer"};
  argv.insert(argv.end(), args);
  return parseCommandLine(static_cast<int>(argv.size()), argv.data());
}

// The run it asks for; a test failure if it is refused.
inline RunConfig parseOk(std::initializer_list<const char*> args) {
  auto result = parse(args);
  if (auto* exit = std::get_if<CliExit>(&result)) {
    ADD_FAILURE() << "exit " << exit->code << ": " << exit->error;
    return {};
  }
  return std::get<RunConfig>(result);
}

// The refusal; a test failure if it parses.
inline CliExit parseFails(std::initializer_list<const char*> args) {
  auto result = parse(args);
  if (auto* exit = std::get_if<CliExit>(&result)) return *exit;
  ADD_FAILURE() << "parsed, expected a failure";
  return {};
}

}  // namespace rt::test
