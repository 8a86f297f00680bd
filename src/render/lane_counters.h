#pragma once
// The SIMD kernel's efficiency counters (--counters): how many rays each
// bounce depth traced, how much traversal and sphere-test work was done,
// and how many of the vector lanes that work occupied were useful. The
// share of lane slots that were not is the thesis' "masking waste" as a
// measured number (docs/thesis.md). Each worker thread tallies into its own
// LaneCounters (no atomics in the hot loop); the renderer sums them once
// per frame. The fields are the schema's frame_csv counter columns.
#include <array>
#include <cstdint>

namespace rt {

// Deepest bounce a scene may ask for (the scene loader's maxDepth limit).
inline constexpr int kCountedDepths = 64;

struct alignas(64) LaneCounters {
  std::array<std::uint64_t, kCountedDepths> raysPerDepth{};  // rays that looked for a sphere, by bounce depth
  std::uint64_t nodeVisits = 0;                              // vector box tests
  std::uint64_t nodeLaneSlots = 0;                           // lanes those tests occupied
  std::uint64_t nodeLanesActive = 0;                         // ... that did useful work
  std::uint64_t sphereTests = 0;                             // vector sphere tests
  std::uint64_t sphereLaneSlots = 0;
  std::uint64_t sphereLanesActive = 0;
  std::uint64_t shadeLaneSlots = 0;    // lanes of the shading steps
  std::uint64_t shadeLanesActive = 0;  // ... whose ray hit a sphere

  LaneCounters& operator+=(const LaneCounters& other) {
    for (std::size_t i = 0; i < raysPerDepth.size(); ++i) raysPerDepth[i] += other.raysPerDepth[i];
    nodeVisits += other.nodeVisits;
    nodeLaneSlots += other.nodeLaneSlots;
    nodeLanesActive += other.nodeLanesActive;
    sphereTests += other.sphereTests;
    sphereLaneSlots += other.sphereLaneSlots;
    sphereLanesActive += other.sphereLanesActive;
    shadeLaneSlots += other.shadeLaneSlots;
    shadeLanesActive += other.shadeLanesActive;
    return *this;
  }
  [[nodiscard]] std::uint64_t rays() const {
    std::uint64_t sum = 0;
    for (const std::uint64_t n : raysPerDepth) sum += n;
    return sum;
  }
  // Depths 0 .. deepestDepth()-1 traced at least one ray.
  [[nodiscard]] int deepestDepth() const {
    int n = kCountedDepths;
    while (n > 0 && raysPerDepth[static_cast<std::size_t>(n - 1)] == 0) --n;
    return n;
  }
};

}  // namespace rt
