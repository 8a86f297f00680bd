#pragma once
#include "render/render_options.h"

namespace rt {

// Which specialisation of a CPU kernel runs: the algorithm, the three early
// exits, the accel (brute force or the BVH), the SIMD kernel's traversal
// of the BVH and its counters are template parameters of the kernels, so
// no option is tested per ray. Chosen once in prepare(); the index numbers
// the specialisations that the SIMD kernel's tables are built over (the
// scalar kernel uses the algorithm, the bounce exit and the accel;
// scalar/scalar_span.h).
struct KernelVariant {
  bool twoPass = false;
  bool bounceExit = false;
  bool sphereExit = false;
  bool discriminantExit = false;
  bool bvh = false;                         // --accel bvh
  Traversal traversal = Traversal::packet;  // with bvh only
  bool counters = false;                    // --counters

  static constexpr unsigned kCount = 128;

  static constexpr KernelVariant of(const RenderOptions& options) {
    return {.twoPass = options.algorithm == Algorithm::two_pass,
            .bounceExit = options.earlyExits.has(EarlyExit::bounce),
            .sphereExit = options.earlyExits.has(EarlyExit::sphere),
            .discriminantExit = options.earlyExits.has(EarlyExit::discriminant),
            .bvh = options.accel == Accel::bvh,
            .traversal = options.accel == Accel::bvh ? options.traversal : Traversal::packet,
            .counters = options.counters};
  }
  // Bits 4-5: 0 brute force, 1 + the traversal with the BVH; bit 6: counters.
  static constexpr KernelVariant fromIndex(unsigned index) {
    const unsigned search = (index >> 4) & 3u;
    return {.twoPass = (index & 1u) != 0,
            .bounceExit = (index & 2u) != 0,
            .sphereExit = (index & 4u) != 0,
            .discriminantExit = (index & 8u) != 0,
            .bvh = search != 0,
            .traversal = search == 0 ? Traversal::packet : static_cast<Traversal>(search - 1),
            .counters = (index & 64u) != 0};
  }
  [[nodiscard]] constexpr unsigned index() const {
    const unsigned search = bvh ? 1u + static_cast<unsigned>(traversal) : 0u;
    return (twoPass ? 1u : 0u) | (bounceExit ? 2u : 0u) | (sphereExit ? 4u : 0u) | (discriminantExit ? 8u : 0u) |
           (search << 4) | (counters ? 64u : 0u);
  }
};

}  // namespace rt
