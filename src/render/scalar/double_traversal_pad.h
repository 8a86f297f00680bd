#pragma once
// The BVH pad for the double-precision reference (src/render/scalar/double_reference.*).
// rt::traversalPad (render/accel/bvh.h) is sized for the float sphere test;
// the reference walks the same float boxes with the double test
// (docs/render-model.md section 3), whose error is far smaller, so its pad is
// its own and smaller (fewer boxes reached), and must still never cull a
// sphere the double test reports a hit on.
#include "render/accel/bvh.h"

namespace rt {

// How far a box is widened, in space and along the ray, for the double test.
// With R the largest radius, M the largest |coordinate| of any box and
// scale = the ray origin's largest |coordinate| + M:
// - the boxes are float: each bound is position +- radius rounded to the
//   nearest float, at most 2^-24 M inside the exact sphere's bound
//   (2^-22 M here, four times that);
// - a hit the double test reports lies within a few double epsilons
//   (2^-53) of (|origin - centre| + R) outside the exact sphere: the
//   rounding of b, f and the discriminant, carried through h = sqrt(disc)
//   to the point origin + t direction, stays linear in the distances; the
//   slab test's own rounding of (bound - origin) / direction is of the same
//   order (2^-40 (scale + R) here, 2^13 epsilons);
// - a term in sqrt(R scale), as the float pad has for tangent rays, at
//   2^-26: a margin should that linear bound miss a case, and still far
//   below the float term.
// Defined in double_reference.cpp; the grazing-ray test in
// tests/render/scalar/double_reference_test.cpp fails with a pad of 0.
double doubleTraversalPad(const Bvh& bvh, double originMaxCoordinate);

}  // namespace rt
