// In-place partition of primitive references by a binned SAH plane, sequential or over a
// TaskPool. Both give the same order for any thread count: the parallel one partitions fixed-size
// chunks (their boundaries depend on the range only) and then swaps the misplaced references of
// the chunks pairwise in chunk order.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/sah_bins.h"
#include "common/task_pool.h"

namespace hrpp::bvh_build {

// The plane: references whose centroid falls in bins [0, bin] on `axis` go left.
struct Plane {
  const BinMap* map;
  int axis;
  int bin;
};

// Partitions refs[begin, end) in place. Ranges up to kChunk references: one two-sided sweep.
// Longer ones: each kChunk-sized chunk on its own (on the pool's threads when given one), then
// the right-going references left of the split swapped with the left-going ones right of it,
// pairwise in chunk order. The order is a function of the input order and the plane only.
// Keeps its scratch arrays between calls: one per thread.
class RefPartitioner {
 public:
  static constexpr std::uint32_t kChunk = 1u << 13;

  // Returns mid: refs[begin, mid) go left, refs[mid, end) right.
  std::uint32_t run(PrimRef* refs, std::uint32_t begin, std::uint32_t end, const Plane& plane,
                      TaskPool* pool = nullptr);

  struct Run {  // references [begin, end) on the wrong side
    std::uint32_t begin, end;
  };

 private:
  struct Chunk {
    std::uint32_t begin = 0, end = 0, mid = 0;
  };
  void collect_misplaced(std::uint32_t mid);
  void swap_misplaced(PrimRef* refs, TaskPool* pool);

  std::vector<Chunk> chunks_;
  std::vector<Run> wrong_right_, wrong_left_;  // right-going refs left of mid; left-going right of it
};

// Below this depth the builders split by SAH; from it on by object median, which bounds the
// tree depth (and so the traversal stack, HRPP_STACK_SIZE) by this + log2(triangles).
constexpr int kMedianSplitDepth = 36;

// Object median on the widest axis of `centroids`: puts the n / 2 references with the lowest
// centroids first (ties in the centroid broken by triangle id, so the halves do not depend on
// the references' order) and returns n / 2.
std::uint32_t median_partition(PrimRef* refs, std::uint32_t n, const Box4& centroids);

}  // namespace hrpp::bvh_build
