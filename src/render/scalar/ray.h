#pragma once
// The scalar kernel's value types, templated on float (the renderers) and
// double (the reference the tests compare against).
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "model_constants.h"

namespace rt::kernel {

template <typename Real>
using Vec3 = glm::vec<3, Real>;

template <typename Real>
struct Ray {
  Vec3<Real> origin;
  Vec3<Real> direction;  // unit
};

template <typename Real>
struct RaycastHit {
  Vec3<Real> position;
  Vec3<Real> normal;
  Real distance;
  int sphere;  // index into the scene's spheres; -1 for a miss
  [[nodiscard]] bool hit() const { return sphere >= 0; }
};

template <typename Real>
constexpr Real kEpsilon = static_cast<Real>(RT_HIT_EPSILON);

}  // namespace rt::kernel
