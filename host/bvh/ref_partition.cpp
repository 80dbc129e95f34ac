#include "bvh/ref_partition.h"

#include <algorithm>
#include <utility>

namespace hrpp::bvh_build {
namespace {

// Says which side a reference goes to, without a branch.
class Classifier {
 public:
  explicit Classifier(const Plane& p)
      : map_(*p.map), limit_(simd::splat3(static_cast<float>(p.bin + 1))), axis_(p.axis) {}
  bool operator()(const PrimRef& ref) const {
    return (simd::bits(simd::less(map_.position(ref.centroid()), limit_)) >> axis_) & 1;
  }

 private:
  const BinMap map_;  // a copy: kept in registers while references are swapped
  const simd::Float4 limit_;
  const int axis_;
};

// Two-sided sweep (Hoare): swaps the first right-going reference from the left with the first
// left-going one from the right. Returns the split.
std::uint32_t sweep(PrimRef* refs, std::uint32_t begin, std::uint32_t end,
                    const Classifier& goes_left) {
  std::uint32_t i = begin, j = end;
  for (;;) {
    while (i < j && goes_left(refs[i])) ++i;
    if (i == j) return i;
    do --j;
    while (i < j && !goes_left(refs[j]));
    if (i == j) return i;
    std::swap(refs[i], refs[j]);
    ++i;
  }
}

// Block partition (Edelkamp and Weiss 2016, BlockQuicksort): classifies blocks of kBlock
// references at both ends without branches, noting the offsets of misplaced ones, then swaps
// them pairwise; what is left in the middle (under two blocks) goes through the sweep.
std::uint32_t partition_range(PrimRef* refs, std::uint32_t begin, std::uint32_t end,
                              const Plane& plane) {
  constexpr std::uint32_t kBlock = 64;
  const Classifier goes_left(plane);
  std::uint8_t wrong_left[kBlock], wrong_right[kBlock];  // right-goers of the left block, ...
  std::uint32_t nl = 0, nr = 0, sl = 0, sr = 0;
  std::uint32_t i = begin, j = end;  // [begin, i) left, [j, end) right
  while (j - i >= 2 * kBlock) {
    if (nl == 0) {
      sl = 0;
      for (std::uint32_t k = 0; k < kBlock; ++k) {
        wrong_left[nl] = static_cast<std::uint8_t>(k);
        nl += !goes_left(refs[i + k]);
      }
    }
    if (nr == 0) {
      sr = 0;
      for (std::uint32_t k = 0; k < kBlock; ++k) {
        wrong_right[nr] = static_cast<std::uint8_t>(k);
        nr += goes_left(refs[j - 1 - k]);
      }
    }
    const std::uint32_t m = std::min(nl, nr);
    for (std::uint32_t k = 0; k < m; ++k)
      std::swap(refs[i + wrong_left[sl + k]], refs[j - 1 - wrong_right[sr + k]]);
    nl -= m, nr -= m, sl += m, sr += m;
    if (nl == 0) i += kBlock;
    if (nr == 0) j -= kBlock;
  }
  return sweep(refs, i, j, goes_left);
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

std::uint32_t RefPartitioner::run(PrimRef* refs, std::uint32_t begin, std::uint32_t end,
                                    const Plane& plane, TaskPool* pool) {
  if (end - begin <= kChunk) return partition_range(refs, begin, end, plane);
  chunks_.clear();
  for (std::uint32_t b = begin; b < end; b += std::min(kChunk, end - b))
    chunks_.push_back({b, b + std::min(kChunk, end - b), 0});
  auto part = [&](std::size_t k, int) {
    chunks_[k].mid = partition_range(refs, chunks_[k].begin, chunks_[k].end, plane);
  };
  if (pool)
    pool->parallel_for(chunks_.size(), part);
  else
    for (std::size_t k = 0; k < chunks_.size(); ++k) part(k, 0);

  std::uint32_t mid = begin;
  for (const Chunk& c : chunks_) mid += c.mid - c.begin;
  collect_misplaced(mid);
  swap_misplaced(refs, pool);
  return mid;
}

void RefPartitioner::collect_misplaced(std::uint32_t mid) {
  wrong_right_.clear();
  wrong_left_.clear();
  for (const Chunk& c : chunks_) {
    const std::uint32_t split = c.mid;  // chunk: [begin, split) left, [split, end) right
    if (split < mid && c.end > split) wrong_right_.push_back({split, std::min(c.end, mid)});
    if (split > mid && c.begin < split) wrong_left_.push_back({std::max(c.begin, mid), split});
  }
}

void RefPartitioner::swap_misplaced(PrimRef* refs, TaskPool* pool) {
  std::size_t count = 0;
  for (const Run& r : wrong_right_) count += r.end - r.begin;
  const std::size_t pieces = chunks(count, kChunk);
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

std::uint32_t median_partition(PrimRef* refs, std::uint32_t n, const Box4& centroids) {
  const float ex = centroids.extent(0), ey = centroids.extent(1), ez = centroids.extent(2);
  const int a = (ex >= ey && ex >= ez) ? 0 : (ey >= ez ? 1 : 2);
  const std::uint32_t mid = n / 2;
  std::nth_element(refs, refs + mid, refs + n, [a](const PrimRef& x, const PrimRef& y) {
    const float cx = 0.5f * (x.lo[a] + x.hi[a]), cy = 0.5f * (y.lo[a] + y.hi[a]);
    return cx < cy || (cx == cy && x.id() < y.id());
  });
  return mid;
}

}  // namespace hrpp::bvh_build
