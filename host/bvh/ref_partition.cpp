#include "bvh/ref_partition.h"

#include <algorithm>
#include <utility>

namespace hrpp::bvh_build {
namespace {

// Two-sided sweep (Hoare): each reference is classified once; its centroid grows the bounds of
// its side.
PartitionResult sweep(PrimRef* refs, std::uint32_t begin, std::uint32_t end, const Plane& p) {
  PartitionResult r;
  auto goes_left = [&](const PrimRef& ref) {
    const simd::Float4 c = ref.centroid();
    alignas(16) std::int32_t bin[4];
    p.map->map(c, bin);
    const bool left = bin[p.axis] <= p.bin;
    (left ? r.left_centroids : r.right_centroids).grow(c);
    return left;
  };
  std::uint32_t i = begin, j = end;
  for (;;) {
    while (i < j && goes_left(refs[i])) ++i;
    if (i == j) break;
    do --j;
    while (i < j && !goes_left(refs[j]));
    if (i == j) break;
    std::swap(refs[i], refs[j]);
    ++i;
  }
  r.mid = i;
  return r;
}

// Walks the references of a list of runs in order, from the `skip`-th on.
class RunCursor {
 public:
  RunCursor(const std::vector<RefPartitioner::Run>& runs, std::size_t skip) : runs_(runs) {
    while (run_ < runs_.size() && skip >= length(run_)) skip -= length(run_++);
    if (run_ < runs_.size()) pos_ = runs_[run_].begin + static_cast<std::uint32_t>(skip);
  }
  std::uint32_t next() {
    const std::uint32_t p = pos_++;
    if (pos_ == runs_[run_].end && ++run_ < runs_.size()) pos_ = runs_[run_].begin;
    return p;
  }

 private:
  std::size_t length(std::size_t run) const { return runs_[run].end - runs_[run].begin; }

  const std::vector<RefPartitioner::Run>& runs_;
  std::size_t run_ = 0;
  std::uint32_t pos_ = 0;
};

}  // namespace

PartitionResult RefPartitioner::run(PrimRef* refs, std::uint32_t begin, std::uint32_t end,
                                    const Plane& plane, TaskPool* pool) {
  if (end - begin <= kChunk) return sweep(refs, begin, end, plane);
  chunks_.clear();
  for (std::uint32_t b = begin; b < end; b += std::min(kChunk, end - b))
    chunks_.push_back({{}, b, b + std::min(kChunk, end - b)});
  auto part = [&](std::size_t k, int) {
    chunks_[k].result = sweep(refs, chunks_[k].begin, chunks_[k].end, plane);
  };
  if (pool)
    pool->parallel_for(chunks_.size(), part);
  else
    for (std::size_t k = 0; k < chunks_.size(); ++k) part(k, 0);

  PartitionResult r;
  r.mid = begin;
  for (const Chunk& c : chunks_) {
    r.mid += c.result.mid - c.begin;
    r.left_centroids.grow(c.result.left_centroids);
    r.right_centroids.grow(c.result.right_centroids);
  }
  collect_misplaced(r.mid);
  swap_misplaced(refs, pool);
  return r;
}

void RefPartitioner::collect_misplaced(std::uint32_t mid) {
  wrong_right_.clear();
  wrong_left_.clear();
  for (const Chunk& c : chunks_) {
    const std::uint32_t split = c.result.mid;  // chunk: [begin, split) left, [split, end) right
    if (split < mid && c.end > split) wrong_right_.push_back({split, std::min(c.end, mid)});
    if (split > mid && c.begin < split) wrong_left_.push_back({std::max(c.begin, mid), split});
  }
}

void RefPartitioner::swap_misplaced(PrimRef* refs, TaskPool* pool) {
  std::size_t count = 0;
  for (const Run& r : wrong_right_) count += r.end - r.begin;
  const std::size_t pieces = (count + kChunk - 1) / kChunk;
  auto swap_piece = [&](std::size_t piece, int) {
    RunCursor a(wrong_right_, piece * kChunk), b(wrong_left_, piece * kChunk);
    const std::size_t n = std::min<std::size_t>(kChunk, count - piece * kChunk);
    for (std::size_t i = 0; i < n; ++i) std::swap(refs[a.next()], refs[b.next()]);
  };
  if (pool)
    pool->parallel_for(pieces, swap_piece);
  else
    for (std::size_t k = 0; k < pieces; ++k) swap_piece(k, 0);
}

}  // namespace hrpp::bvh_build
