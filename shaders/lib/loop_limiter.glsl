// The loop-limiter probe every kernel that must prove it finished runs after its work
// (docs/DEVICES.md, "Lavapipe": lavapipe silently ends loops once a subgroup has run 65,535
// iterations). Needs a push-constant block `pc` with a canary_iterations member (always 2).
#ifndef HRPP_LOOP_LIMITER_GLSL
#define HRPP_LOOP_LIMITER_GLSL

// True while the loop limiter has budget left: a loop of pc.canary_iterations (2) iterations
// runs in full. Once a limiter has fired, loops run once, so this reads false from then on.
bool loop_budget_left() {
  uint n = 0u;
  for (uint i = 0u; i < pc.canary_iterations; ++i) ++n;
  return n == pc.canary_iterations;
}

#endif  // HRPP_LOOP_LIMITER_GLSL
