#include "render/accel/centre_region.h"

#include <algorithm>
#include <cstddef>
#include <glm/vector_relational.hpp>
#include <stdexcept>
#include <vector>

namespace rt {

CentreRegion typicalCentreRegion(std::span<const Sphere> spheres) {
  if (spheres.empty()) throw std::invalid_argument("the centre region needs at least one sphere");
  CentreRegion region;
  std::vector<float> values(spheres.size());
  const auto low = static_cast<std::ptrdiff_t>(spheres.size() / 20);
  const auto high = static_cast<std::ptrdiff_t>(spheres.size() - 1 - spheres.size() / 20);
  for (int a = 0; a < 3; ++a) {
    std::ranges::transform(spheres, values.begin(), [a](const Sphere& s) { return s.position[a]; });
    std::ranges::nth_element(values, values.begin() + low);
    region.lo[a] = values[static_cast<std::size_t>(low)];
    std::ranges::nth_element(values, values.begin() + high);
    region.hi[a] = values[static_cast<std::size_t>(high)];
  }
  region.centres = static_cast<std::size_t>(std::ranges::count_if(spheres, [&](const Sphere& s) {
    return glm::all(glm::greaterThanEqual(s.position, region.lo)) &&
           glm::all(glm::lessThanEqual(s.position, region.hi));
  }));
  return region;
}

}  // namespace rt
