// The trace kernels' counters block (TraceCounters, shaders/shared/trace_interface.h) at
// binding HRPP_COUNTERS_BINDING, and the add of a subgroup's sum to one of its 64-bit counters.
#ifndef HRPP_TRACE_COUNTERS_GLSL
#define HRPP_TRACE_COUNTERS_GLSL

layout(std430, set = 0, binding = HRPP_COUNTERS_BINDING) restrict buffer CounterBuffer {
  TraceCounters counters;
};

// counters.wide[counter] += value, as a (lo, hi) pair of 32-bit atomics.
void add_wide(uint counter, uint value) {
  if (value == 0u) return;
  const uint old = atomicAdd(counters.wide[2u * counter], value);
  if (old + value < old) atomicAdd(counters.wide[2u * counter + 1u], 1u);  // carry
}

#endif  // HRPP_TRACE_COUNTERS_GLSL
