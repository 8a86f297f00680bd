#pragma once
#include "render/render_options.h"

namespace rt {

// Which specialisation of a CPU kernel runs: the algorithm and the three
// early exits are template parameters of the kernels, so no option is
// tested per ray. Chosen once in prepare(); the index numbers the
// specialisations that the SIMD kernel's tables are built over.
struct KernelVariant {
  bool twoPass = false;
  bool bounceExit = false;
  bool sphereExit = false;
  bool discriminantExit = false;

  static constexpr unsigned kCount = 16;

  static constexpr KernelVariant of(const RenderOptions& options) {
    return {.twoPass = options.algorithm == Algorithm::two_pass,
            .bounceExit = options.earlyExits.has(EarlyExit::bounce),
            .sphereExit = options.earlyExits.has(EarlyExit::sphere),
            .discriminantExit = options.earlyExits.has(EarlyExit::discriminant)};
  }
  static constexpr KernelVariant fromIndex(unsigned index) {
    return {.twoPass = (index & 1u) != 0,
            .bounceExit = (index & 2u) != 0,
            .sphereExit = (index & 4u) != 0,
            .discriminantExit = (index & 8u) != 0};
  }
  [[nodiscard]] constexpr unsigned index() const {
    return (twoPass ? 1u : 0u) | (bounceExit ? 2u : 0u) | (sphereExit ? 4u : 0u) | (discriminantExit ? 8u : 0u);
  }
};

}  // namespace rt
