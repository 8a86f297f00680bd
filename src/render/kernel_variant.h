#pragma once
#include "render/render_options.h"

namespace rt {

// Which specialisation of a CPU kernel runs: the algorithm, the three early
// exits and the accel (brute force or the BVH) are template parameters of
// the kernels, so no option is tested per ray. Chosen once in prepare();
// the index numbers the specialisations that the SIMD kernel's tables are
// built over (the scalar kernel uses the algorithm, the bounce exit and
// the accel; scalar/scalar_span.h).
struct KernelVariant {
  bool twoPass = false;
  bool bounceExit = false;
  bool sphereExit = false;
  bool discriminantExit = false;
  bool bvh = false;  // --accel bvh

  static constexpr unsigned kCount = 32;

  static constexpr KernelVariant of(const RenderOptions& options) {
    return {.twoPass = options.algorithm == Algorithm::two_pass,
            .bounceExit = options.earlyExits.has(EarlyExit::bounce),
            .sphereExit = options.earlyExits.has(EarlyExit::sphere),
            .discriminantExit = options.earlyExits.has(EarlyExit::discriminant),
            .bvh = options.accel == Accel::bvh};
  }
  static constexpr KernelVariant fromIndex(unsigned index) {
    return {.twoPass = (index & 1u) != 0,
            .bounceExit = (index & 2u) != 0,
            .sphereExit = (index & 4u) != 0,
            .discriminantExit = (index & 8u) != 0,
            .bvh = (index & 16u) != 0};
  }
  [[nodiscard]] constexpr unsigned index() const {
    return (twoPass ? 1u : 0u) | (bounceExit ? 2u : 0u) | (sphereExit ? 4u : 0u) | (discriminantExit ? 8u : 0u) |
           (bvh ? 16u : 0u);
  }
};

}  // namespace rt
