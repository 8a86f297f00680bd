// Compiled once per Highway target: foreach_target.h re-includes this file
// for every target, each time with a different HWY_NAMESPACE and target
// attributes; the HWY_ONCE part at the end is compiled only once and holds
// the dispatch. Keep this file and its includes light: it costs one compile
// per target.

// The plain header first, as in Highway's skeleton: it has no Highway types,
// so neither the target list nor foreach_target.h concern it.
#include "render/simd/packet_kernels.h"

#include <algorithm>

#include "render/simd/kernel_targets.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/simd/packet_kernels.cc"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "render/simd/packet_kernel-inl.h"

HWY_BEFORE_NAMESPACE();
namespace rt::simd::HWY_NAMESPACE {

// The variants without counters; packet_kernels_counted.cc has the others.
TargetKernels GetTargetKernels() { return HalfOfTargetKernels<0>(); }

// This compile's entry in compiledTargets(): the build's own word for what
// it holds, which a CPU without this target cannot ask of dispatch.
[[maybe_unused]] const bool kListed = listCompiledTarget({HWY_TARGET, RT_SIMD_NATIVE_F16 != 0});

}  // namespace rt::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace rt::simd {

HWY_EXPORT(GetTargetKernels);

// Both halves come from the same target: dispatch picks the best one this
// CPU supports (or a test's forced one) the same way in both files.
TargetKernels dispatchedKernels() {
  TargetKernels kernels = HWY_DYNAMIC_DISPATCH(GetTargetKernels)();
  const TargetKernels counted = dispatchedCountedKernels();
  const auto merge = [](LaneKernels& into, const LaneKernels& from) {
    for (unsigned i = 0; i < KernelVariant::kCount; ++i) {
      if (from.variants[i] != nullptr) into.variants[i] = from.variants[i];
    }
  };
  const auto mergeSet = [&](LaneSet& into, const LaneSet& from) {
    merge(into.native, from.native);
    for (std::size_t i = 0; i < into.capped.size(); ++i) merge(into.capped[i], from.capped[i]);
  };
  mergeSet(kernels.f32, counted.f32);
  mergeSet(kernels.f16, counted.f16);
  return kernels;
}

std::string targetName(std::int64_t target) { return hwy::TargetName(target); }

std::string highwayVersion() {
  return std::to_string(HWY_MAJOR) + "." + std::to_string(HWY_MINOR) + "." + std::to_string(HWY_PATCH);
}

// HWY_TARGETS here is this file's list, which excludes the disabled targets.
std::vector<std::int64_t> availableTargets() {
  std::vector<std::int64_t> targets;
  for (std::int64_t t = hwy::SupportedTargets() & HWY_TARGETS; t != 0; t &= t - 1) targets.push_back(t & -t);
  return targets;
}

namespace {
std::vector<CompiledTarget>& compiledTargetList() {
  static std::vector<CompiledTarget> list;
  return list;
}

// The targets whose kernels have f16 lanes where the build compiles them:
// native f16 arithmetic in Highway 1.2 and newer (packet_kernel-inl.h,
// RT_SIMD_NATIVE_F16). The x86 one is the only target a build of ours
// leaves out (kernel_targets.h).
constexpr std::int64_t kHalfPrecisionTargets =
#if HWY_MAJOR > 1 || HWY_MINOR >= 2
    HWY_AVX3_SPR;
#else
    0;
#endif
}  // namespace

bool listCompiledTarget(CompiledTarget target) {
  compiledTargetList().push_back(target);
  return true;
}

std::vector<CompiledTarget> compiledTargets() {
  std::vector<CompiledTarget> list = compiledTargetList();
  std::ranges::sort(list, {}, &CompiledTarget::target);  // a lower bit is a better target
  return list;
}

std::vector<std::int64_t> halfPrecisionTargetsLeftOut() {
  std::vector<std::int64_t> targets;
  const std::int64_t leftOut = hwy::SupportedTargets() & kHalfPrecisionTargets & ~HWY_TARGETS;
  for (std::int64_t t = leftOut; t != 0; t &= t - 1) targets.push_back(t & -t);
  return targets;
}

ScopedTargetOverride::ScopedTargetOverride(std::int64_t target) { hwy::SetSupportedTargetsForTest(target); }
ScopedTargetOverride::~ScopedTargetOverride() { hwy::SetSupportedTargetsForTest(0); }

}  // namespace rt::simd
#endif  // HWY_ONCE
