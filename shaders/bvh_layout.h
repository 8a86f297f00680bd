// The BVH of --accel bvh as C++ (src/render/accel/bvh.h) builds it and
// both the CPU kernels and shaders/raytrace.comp walk it: shared by C++ and
// GLSL, so #defines only.
#ifndef RT_BVH_LAYOUT_H
#define RT_BVH_LAYOUT_H

// A node's last word: a leaf's sphere count in the low 30 bits (0 for an
// inner node, whose split axis sits in the top 2).
#define RT_BVH_COUNT_MASK 0x3fffffffu
// The deepest tree the build makes; it sizes every traversal stack.
#define RT_BVH_MAX_DEPTH 48

// The traversal pad (rt::traversalPad): how far a box is widened so that no
// sphere the float test reports a hit on is culled with it. With
// scale = max |origin component| + the scene's largest |coordinate| and R
// the largest radius: pad = A scale + B sqrt(R scale) + C R + D.
#define RT_BVH_PAD_SCALE 1e-5
#define RT_BVH_PAD_TANGENT 3e-3
#define RT_BVH_PAD_RADIUS 2e-3
#define RT_BVH_PAD_MIN 1e-6
// Local padding (rt::BoxPadding::local) splits the tangency term
// sqrt(R o) <= (SPLIT R + o / SPLIT) / 2 between a box (its spheres' R) and
// the ray (its origin o); 4 balances the two for radii near 1 seen from
// about 16 units, the committed scenes' scale.
#define RT_BVH_PAD_SPLIT 4.0

#endif
