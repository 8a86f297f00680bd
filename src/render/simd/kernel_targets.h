#pragma once
// The Highway targets both halves of the packet kernels (packet_kernels.cc,
// packet_kernels_counted.cc) are compiled for: included before
// foreach_target.h, so that the two always agree.
//
// SVE and SVE2 run at the machine's vector length (the packet types hold
// scalable vectors in memory: packet_kernel-inl.h, "Holding vectors").
// Left out: SVE_256 and SVE2_128, Highway's copies of those two for one
// vector length each, which would add two compiles of the kernels for what
// SVE and SVE2 already run; and RVV, which no machine of ours can test.
//
// With RT_SIMD_FEWER_TARGETS (the debug preset, whose sanitizers make each
// compile slow) x86 keeps one target per packet width: AVX3 (16 float
// lanes), AVX2 (8), SSE4 (4) and the baseline. It leaves out SSSE3 and every
// target above AVX3 (whose bits lie below HWY_AVX3's in each Highway version).
#if defined(RT_SIMD_FEWER_TARGETS) && RT_SIMD_FEWER_TARGETS
#define RT_SIMD_SKIPPED_TARGETS (HWY_SSSE3 | (HWY_AVX3 - 1))
#else
#define RT_SIMD_SKIPPED_TARGETS 0
#endif
#define HWY_DISABLED_TARGETS (HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV | RT_SIMD_SKIPPED_TARGETS)
