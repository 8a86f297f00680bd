// Lavapipe's loop limit (docs/render-model.md section 8). Its compiler
// (gallivm) counts every iteration of every loop of a subgroup (its SIMD
// vector) and, once the count reaches RT_LAVAPIPE_LOOP_ITERATIONS, ends
// each loop after one pass of its body, without an error: the image is cut
// short. With LOOP_GUARD (set on lavapipe) the shader ends with a loop that
// takes two passes unless the count has reached the limit; its bound is
// read from the guard buffer, so no compiler can unroll it or know it. One
// pass means a loop before it was cut short: the shader raises the guard
// word, and the renderer fails the frame.
void reportLoopLimit() {
  if (!LOOP_GUARD) return;
  uint passes = 0u;
  for (uint i = 0u; i < loopGuardWords[1] + 2u; ++i) ++passes;
  if (passes < 2u) atomicMax(loopGuardWords[0], 1u);
}
