// The passes of the HRPP stage over one trace's rays (StagePushConstants::pilot_pass), compiled
// by the host (C++20) and by GLSL from this one definition:
//   HRPP_PASS_ALL     every ray;
//   HRPP_PASS_PILOTS  the pilot schedule's first pass: every stride-th ray;
//   HRPP_PASS_OTHERS  its second pass: the rays between the pilots;
//   HRPP_PASS_SAMPLE  the adaptive predictor's sample: every stride-th block of
//                     HRPP_SAMPLE_BLOCK consecutive rays (blocks keep neighbouring rays
//                     together in a subgroup, as in the whole trace; spreading the blocks
//                     covers the whole image);
//   HRPP_PASS_NONE    no ray: a dispatch that only measures what a dispatch costs (the
//                     adaptive predictor subtracts it from a sample's time).
// hrpp_pass_ray_count(total, ...) is the pass's ray count, hrpp_pass_ray_index(j, ...) the
// index of its j-th ray.
#ifndef HRPP_HRPP_PASSES_H
#define HRPP_HRPP_PASSES_H

#define HRPP_PASS_ALL 0u
#define HRPP_PASS_PILOTS 1u
#define HRPP_PASS_OTHERS 2u
#define HRPP_PASS_SAMPLE 3u
#define HRPP_PASS_NONE 4u
#define HRPP_SAMPLE_BLOCK 256u

#include "shared_fn.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

HRPP_SHARED_FN uint hrpp_pass_ray_count(uint total, uint pass, uint stride) {
  if (pass == HRPP_PASS_ALL) return total;
  if (pass == HRPP_PASS_NONE) return 0u;
  if (pass == HRPP_PASS_SAMPLE) {
    const uint period = HRPP_SAMPLE_BLOCK * stride;
    const uint rest = total % period;
    const uint last = rest < HRPP_SAMPLE_BLOCK ? rest : HRPP_SAMPLE_BLOCK;
    return (total / period) * HRPP_SAMPLE_BLOCK + last;
  }
  const uint pilots = (total + stride - 1u) / stride;
  return pass == HRPP_PASS_PILOTS ? pilots : total - pilots;
}

HRPP_SHARED_FN uint hrpp_pass_ray_index(uint j, uint pass, uint stride) {
  if (pass == HRPP_PASS_ALL) return j;
  if (pass == HRPP_PASS_SAMPLE)
    return (j / HRPP_SAMPLE_BLOCK) * HRPP_SAMPLE_BLOCK * stride + j % HRPP_SAMPLE_BLOCK;
  if (pass == HRPP_PASS_PILOTS) return j * stride;
  const uint others = stride - 1u;  // rays between two pilots
  return (j / others) * stride + j % others + 1u;
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_HRPP_PASSES_H
