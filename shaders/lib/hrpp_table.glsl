// The HRPP predictor table of one ray class on the GPU: sets × ways entries, each a 64-bit tag
// (the full key; all ones = empty), a use stamp and `nodes` node slots (HRPP_EMPTY_NODE =
// empty). A key lives in the set hrpp_entry_base gives (shaders/shared/hrpp_table_set.h), in any
// of its ways. Concurrent rays update it with compare-and-swap on tags and slots, so a node list never holds a node twice (a slot is
// claimed only by a CAS from empty, after every earlier slot was seen holding another node).
//
// Policies (PredictorParams.policy), when an insert finds no room:
//   none: drop it (the paper's table has no replacement);
//   lru:  no free way: the way with the oldest use stamp (probe hits and inserts renew it) is
//         evicted (tag swapped by CAS, slots emptied); full node list: the slot (stamp mod
//         nodes) is overwritten. Both count as evictions.
//   fifo: as lru, but a way's stamp is the clock at which its key came in (an empty way
//         claimed, or a victim replaced), never renewed: the oldest key is evicted, and a probe
//         hit writes nothing to the table.
//   micro21: MICRO'21's table: a key's set is its bits xor-folded to the set count's width;
//         otherwise as lru (its source evicts a full list's least recently used node; with its
//         published one node an entry the two are the same).
// Stamps are the ray's clock (PredictorParams.clock + ray index), so they wrap after 2^32 rays.
// With the distance gate (PredictorParams.gate > 0) the stamp buffer holds after the sets × ways
// stamps each entry's nearest hit (shaders/shared/hrpp_distance_gate.h): inserts raise it, a key
// that comes in clears it.
//
// The includer defines HRPP_TABLE_BASE (first binding) and enables 64-bit integers and atomics.
#ifndef HRPP_TABLE_GLSL
#define HRPP_TABLE_GLSL

#include "hrpp_distance_gate.h"
#include "hrpp_interface.h"
#include "hrpp_table_set.h"

layout(std430, set = 0, binding = HRPP_TABLE_BASE + HRPP_TABLE_PARAMS) readonly restrict buffer
    HrppParamBuffer {
  PredictorParams hrpp;
};
layout(std430, set = 0, binding = HRPP_TABLE_BASE + HRPP_TABLE_TAGS) restrict buffer HrppTagBuffer {
  uint64_t hrpp_tags[];
};
// The same tags as 32-bit words for plain loads (only the atomics need 64-bit access).
layout(std430, set = 0, binding = HRPP_TABLE_BASE + HRPP_TABLE_TAGS) buffer
    HrppTagWordBuffer {
  uint hrpp_tag_words[];
};
uint64_t hrpp_load_tag(uint i) {
  return uint64_t(hrpp_tag_words[2u * i]) | (uint64_t(hrpp_tag_words[2u * i + 1u]) << 32);
}

layout(std430, set = 0, binding = HRPP_TABLE_BASE + HRPP_TABLE_STAMPS) restrict buffer
    HrppStampBuffer {
  uint hrpp_stamps[];
};
layout(std430, set = 0, binding = HRPP_TABLE_BASE + HRPP_TABLE_SLOTS) restrict buffer
    HrppSlotBuffer {
  uint hrpp_slots[];
};
layout(std430, set = 0, binding = HRPP_TABLE_BASE + HRPP_TABLE_REQUESTS) restrict buffer
    HrppRequestBuffer {
  InsertRequest hrpp_requests[];
};
// The class's PredictorCounters (64-bit counts) as 32-bit words, low word first: a kernel adds
// to the low word and carries into the high one (hrpp_add_counter), exact without 64-bit atomics.
layout(std430, set = 0, binding = HRPP_TABLE_BASE + HRPP_TABLE_COUNTERS) restrict buffer
    HrppCounterBuffer {
  uint hrpp_counter_words[];
};

// Entry e's nearest-hit word (the distance gate's): in the stamp buffer, after the stamps.
uint hrpp_nearest_index(uint e) {
  return hrpp_table_count(hrpp.sm_tables) * hrpp.sets * hrpp.ways + e;
}

const uint64_t kHrppEmptyTag = ~uint64_t(0);
const uint kHrppEmptyNode = uint(HRPP_EMPTY_NODE);

// Outcomes of hrpp_table_insert.
const uint kHrppInserted = 0u;
const uint kHrppPresent = 1u;
const uint kHrppDropped = 2u;

// No return or continue inside loops here: on lavapipe (Mesa 22.3) an early return from a loop
// in divergent control flow gave wrong answers (measured: most probes of keys in the table
// missed with 8 lanes active, none with one); loops carry a state variable instead.

// How lookups read a tag: the includer may name a faster read (HRPP_TABLE_FETCH_TAG: the
// stage's texel view); inserts always use the storage buffer they update.
#ifndef HRPP_TABLE_FETCH_TAG
#define HRPP_TABLE_FETCH_TAG hrpp_load_tag
#endif

// Entry index holding `key`, or -1. A hit renews the entry's stamp (lru).
int hrpp_table_lookup(uint64_t key, uint clock) {
  const uint base = hrpp_entry_base(key, hrpp.sets, hrpp.ways, hrpp.policy);
  int found = -1;
  for (uint w = 0u; w < hrpp.ways; ++w)
    if (found < 0 && HRPP_TABLE_FETCH_TAG(base + w) == key) found = int(base + w);
  if (found >= 0 && hrpp_renews_stamps(hrpp.policy)) atomicMax(hrpp_stamps[found], clock);
  return found;
}

// Inserts node `node`, found by a traced ray at `t`, under `key`; returns kHrppInserted /
// kHrppPresent / kHrppDropped and adds the entries and nodes it replaced to `evictions`.
uint hrpp_table_insert(uint64_t key, int node, float t, uint clock, inout uint evictions) {
  const uint base = hrpp_entry_base(key, hrpp.sets, hrpp.ways, hrpp.policy);
  int entry = -1;
  bool claimed = false;  // this insert brought the key in (fifo's stamp)
  for (uint w = 0u; w < hrpp.ways && entry < 0; ++w) {
    const uint64_t tag = hrpp_load_tag(base + w);
    if (tag == key) {
      entry = int(base + w);
    } else if (tag == kHrppEmptyTag) {
      const uint64_t prev = atomicCompSwap(hrpp_tags[base + w], kHrppEmptyTag, key);
      if (prev == kHrppEmptyTag || prev == key) entry = int(base + w);
      claimed = prev == kHrppEmptyTag;
    }
  }
  if (entry < 0) {
    if (hrpp.policy == HRPP_POLICY_NONE) return kHrppDropped;
    uint victim = base;
    for (uint w = 1u; w < hrpp.ways; ++w)
      if (hrpp_stamps[base + w] < hrpp_stamps[victim]) victim = base + w;
    const uint64_t old = hrpp_load_tag(victim);
    const uint64_t prev = atomicCompSwap(hrpp_tags[victim], old, key);
    if (prev != old && prev != key) return kHrppDropped;  // another ray replaced it first
    if (prev == old && old != key) {
      claimed = true;
      ++evictions;
      for (uint s = 0u; s < hrpp.nodes; ++s)
        atomicExchange(hrpp_slots[victim * hrpp.nodes + s], kHrppEmptyNode);
    }
    entry = int(victim);
  }
  if (hrpp_renews_stamps(hrpp.policy) || (hrpp.policy == HRPP_POLICY_FIFO && claimed))
    atomicMax(hrpp_stamps[entry], clock);
  if (hrpp.gate > 0.0) {
    if (claimed) atomicExchange(hrpp_stamps[hrpp_nearest_index(uint(entry))], 0u);
    atomicMax(hrpp_stamps[hrpp_nearest_index(uint(entry))], hrpp_nearest_word(t));
  }
  const uint first = uint(entry) * hrpp.nodes;
  uint outcome = kHrppDropped;  // until a slot holds the node
  for (uint s = 0u; s < hrpp.nodes && outcome == kHrppDropped; ++s) {
    uint held = hrpp_slots[first + s];
    if (held == kHrppEmptyNode)
      held = atomicCompSwap(hrpp_slots[first + s], kHrppEmptyNode, uint(node));
    if (held == kHrppEmptyNode) outcome = kHrppInserted;
    else if (held == uint(node)) outcome = kHrppPresent;
  }
  if (outcome == kHrppDropped && hrpp_replaces_nodes(hrpp.policy)) {
    atomicExchange(hrpp_slots[first + clock % hrpp.nodes], uint(node));
    ++evictions;
    outcome = kHrppInserted;
  }
  return outcome;
}

void hrpp_add_counter(uint counter, uint value) {
  if (value == 0u) return;
  const uint before = atomicAdd(hrpp_counter_words[2u * counter], value);
  if (before + value < before) atomicAdd(hrpp_counter_words[2u * counter + 1u], 1u);
}

// A kernel's counts of a counter list (HRPP_*_COUNTERS, shaders/shared/hrpp_types.h): it declares
// one `uint count_<key>` per counter with HRPP_DECLARE_COUNT and adds them to the class's counters
// once, at the end, with HRPP_FLUSH_COUNTS (summed over the subgroup) or, in a single invocation,
// with HRPP_ADD_COUNT. The lists expand to one statement per counter: no loop, which the loop
// limiter could cut short (docs/DEVICES.md, "Lavapipe").
#define HRPP_DECLARE_COUNT(NAME, key, index) uint count_##key = 0u;
#define HRPP_ADD_COUNT(NAME, key, index) hrpp_add_counter(index, count_##key);
#define HRPP_SUM_COUNT(NAME, key, index) sums[index] = subgroupAdd(count_##key);
#define HRPP_ADD_SUM(NAME, key, index) hrpp_add_counter(index, sums[index]);
#define HRPP_FLUSH_COUNTS(LIST)                                  \
  {                                                              \
    uint sums[HRPP_PC_COUNT];                                    \
    LIST(HRPP_SUM_COUNT)                                         \
    if (subgroupElect()) {                                       \
      LIST(HRPP_ADD_SUM)                                         \
    }                                                            \
  }

#endif  // HRPP_TABLE_GLSL
