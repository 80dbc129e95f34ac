// The trace kernels' counters block (TraceCounters, shaders/shared/trace_interface.h) at
// binding HRPP_COUNTERS_BINDING: the persistent invocations' fetch of their next positions
// from its cursor, and the add of a subgroup's sum to one of its 64-bit counters.
#ifndef HRPP_TRACE_COUNTERS_GLSL
#define HRPP_TRACE_COUNTERS_GLSL

layout(std430, set = 0, binding = HRPP_COUNTERS_BINDING) restrict buffer CounterBuffer {
  TraceCounters counters;
};

// The next position of a persistent invocation's loop: one atomicAdd on the cursor per
// subgroup for all its active lanes (any subgroup size). `more` turns false, uniformly across
// the subgroup, once the cursor has passed counters.ray_count; within the last fetch a lane's
// position may lie past it.
uint fetch_position(out bool more) {
  const uvec4 lanes = subgroupBallot(true);
  uint base = 0u;
  if (subgroupElect()) base = atomicAdd(counters.next_ray, subgroupBallotBitCount(lanes));
  base = subgroupBroadcastFirst(base);
  more = base < counters.ray_count;
  return base + subgroupBallotExclusiveBitCount(lanes);
}

// counters.wide[counter] += value, as a (lo, hi) pair of 32-bit atomics.
void add_wide(uint counter, uint value) {
  if (value == 0u) return;
  const uint old = atomicAdd(counters.wide[2u * counter], value);
  if (old + value < old) atomicAdd(counters.wide[2u * counter + 1u], 1u);  // carry
}

#endif  // HRPP_TRACE_COUNTERS_GLSL
