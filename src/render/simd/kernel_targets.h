#pragma once
// The Highway targets both halves of the packet kernels (packet_kernels.cc,
// packet_kernels_counted.cc) are compiled for: included before
// foreach_target.h, so that the two always agree.
//
// Scalable vectors (SVE, RVV) are sizeless types that cannot be members of
// the packet structs (Vec3x, RayX); Arm machines with SVE run NEON instead.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif
