#pragma once
#include <functional>
#include <string_view>

#include "app/run_config.h"

namespace rt {

// What the raytracer and rt_agreement share around their work: the command
// line parsed (help, version and bad options answered there), then `run`,
// whose failures each become a line on stderr, "<program>: ...", and the
// exit code cli.h gives that kind of failure.
int runProgram(std::string_view program, int argc, char** argv, const std::function<int(const RunConfig&)>& run);

}  // namespace rt
