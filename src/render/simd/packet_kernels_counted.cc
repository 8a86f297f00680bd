// The SIMD kernel's variants with counters (--counters): the upper half of
// the variant table, compiled apart from packet_kernels.cc so that the two
// halves compile side by side. Compiled once per Highway target, as there.

#include "render/simd/kernel_targets.h"
#include "render/simd/packet_kernels.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/simd/packet_kernels_counted.cc"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "render/simd/packet_kernel-inl.h"

HWY_BEFORE_NAMESPACE();
namespace rt::simd::HWY_NAMESPACE {

TargetKernels GetCountedKernels() { return HalfOfTargetKernels<kHalfVariants>(); }

}  // namespace rt::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace rt::simd {

HWY_EXPORT(GetCountedKernels);

TargetKernels dispatchedCountedKernels() { return HWY_DYNAMIC_DISPATCH(GetCountedKernels)(); }

}  // namespace rt::simd
#endif  // HWY_ONCE
