// Compiled once per Highway target: foreach_target.h re-includes this file
// for every target, each time with a different HWY_NAMESPACE and target
// attributes; the HWY_ONCE part at the end is compiled only once and holds
// the dispatch. Keep this file and its includes light: it costs one compile
// per target.

// The plain header first, as in Highway's skeleton: it has no Highway types,
// so neither the target list nor foreach_target.h concern it.
#include "render/simd/packet_kernels.h"

// Scalable vectors (SVE, RVV) are sizeless types that cannot be members of
// the packet structs (Vec3x, RayX); Arm machines with SVE run NEON instead.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/simd/packet_kernels.cc"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "render/simd/packet_kernel-inl.h"

HWY_BEFORE_NAMESPACE();
namespace rt::simd::HWY_NAMESPACE {

template <std::size_t... kIndex>
std::array<LaneKernels, sizeof...(kIndex)> AllCappedKernels(std::index_sequence<kIndex...>) {
  return {CappedKernels<static_cast<std::size_t>(schema::kLaneWidths[kIndex])>()...};
}

// What this target offers: the native width and each of the schema's lane
// widths. Returned by value through dispatch, so callers keep this target's
// function pointers and never dispatch per row.
TargetKernels GetTargetKernels() {
  const hn::ScalableTag<float> d;
  TargetKernels kernels;
  kernels.target = HWY_TARGET;
  kernels.nativeLanes = static_cast<int>(hn::Lanes(d));
  kernels.native = MakeLaneKernels(d, std::make_integer_sequence<unsigned, KernelVariant::kCount>());
  kernels.capped = AllCappedKernels(std::make_index_sequence<schema::kLaneWidths.size()>());
  return kernels;
}

}  // namespace rt::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace rt::simd {

HWY_EXPORT(GetTargetKernels);

TargetKernels dispatchedKernels() { return HWY_DYNAMIC_DISPATCH(GetTargetKernels)(); }

std::string targetName(std::int64_t target) { return hwy::TargetName(target); }

// HWY_TARGETS here is this file's list, which excludes the disabled targets.
std::vector<std::int64_t> availableTargets() {
  std::vector<std::int64_t> targets;
  for (std::int64_t t = hwy::SupportedTargets() & HWY_TARGETS; t != 0; t &= t - 1) targets.push_back(t & -t);
  return targets;
}

ScopedTargetOverride::ScopedTargetOverride(std::int64_t target) { hwy::SetSupportedTargetsForTest(target); }
ScopedTargetOverride::~ScopedTargetOverride() { hwy::SetSupportedTargetsForTest(0); }

}  // namespace rt::simd
#endif  // HWY_ONCE
