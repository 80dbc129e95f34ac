// The set of an HRPP predictor table that holds a key: (key × the 64-bit golden-ratio constant)
// >> 32, modulo the power-of-two set count; under MICRO'21's policy its 48 key bits xor-folded
// in chunks of the set count's width, as its table indexes (ray-predictor.cc, compute_index);
// the policies' shared rules and per-SM tables. One definition for the GPU table
// (shaders/lib/hrpp_table.glsl) and its CPU mirror (host/hrpp/reference_table.cpp). GLSL
// includers enable 64-bit integers first.
#ifndef HRPP_HRPP_TABLE_SET_H
#define HRPP_HRPP_TABLE_SET_H

#include "hrpp_types.h"
#include "shared_fn.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

HRPP_SHARED_FN uint hrpp_set_of(uint64_t key, uint sets) {
  return uint((key * 0x9E3779B97F4A7C15ul) >> 32) & (sets - 1u);
}

// The set bits of v (SWAR; no loop).
HRPP_SHARED_FN uint hrpp_popcount(uint v) {
  v = v - ((v >> 1) & 0x55555555u);
  v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
  return (((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24;
}

HRPP_SHARED_FN uint hrpp_folded_set(uint64_t key, uint sets) {
  if (sets <= 1u) return 0u;
  const uint bits = hrpp_popcount(sets - 1u);  // log2 of the power of two
  const uint64_t k = key & ((uint64_t(1) << HRPP_KEY_BITS) - 1u);  // the table rides above
  uint set = 0u;
  for (uint s = 0u; s < HRPP_KEY_BITS; s += bits) set ^= uint(k >> s) & (sets - 1u);
  return set;
}

HRPP_SHARED_FN uint hrpp_set_index(uint64_t key, uint sets, uint policy) {
  if (policy == HRPP_POLICY_MICRO21) return hrpp_folded_set(key, sets);
  return hrpp_set_of(key, sets);
}

// Per-SM tables (sm_tables K > 1), the hardware predictor's setting: K independent tables, each
// of sets × ways entries. A ray's table is that of its block of HRPP_SM_BLOCK consecutive rays in
// launch order (its use clock: the class's rays counted over its traces), dealt round robin, as
// a GPU hands workgroups to its SMs. The table rides in the key above its HRPP_KEY_BITS, so that
// every later use of the key (the queue, deferred inserts) finds the same table.
#define HRPP_SM_BLOCK 64u
HRPP_SHARED_FN uint hrpp_table_count(uint sm_tables) { return sm_tables > 1u ? sm_tables : 1u; }
HRPP_SHARED_FN uint64_t hrpp_sm_key(uint64_t key, uint clock, uint sm_tables) {
  return sm_tables > 1u ? key | (uint64_t((clock / HRPP_SM_BLOCK) % sm_tables) << HRPP_KEY_BITS)
                        : key;
}
// The first entry of the set that holds `key`: its table's, then the set within it.
HRPP_SHARED_FN uint hrpp_entry_base(uint64_t key, uint sets, uint ways, uint policy) {
  return (uint(key >> HRPP_KEY_BITS) * sets + hrpp_set_index(key, sets, policy)) * ways;
}

// The policies' rules that both sides branch on: whether probe hits and inserts renew a way's
// use stamp (the oldest is the victim), and whether an insert into a full node list overwrites
// a slot (else it is dropped).
HRPP_SHARED_FN bool hrpp_renews_stamps(uint policy) {
  return policy == HRPP_POLICY_LRU || policy == HRPP_POLICY_MICRO21;
}
HRPP_SHARED_FN bool hrpp_replaces_nodes(uint policy) { return policy != HRPP_POLICY_NONE; }

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_HRPP_TABLE_SET_H
