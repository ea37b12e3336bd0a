// A2, the greedy conversion of thesis 4.5.4 (GMax of Botella 2016): pop the
// best candidate (Eq. 4.1) and adopt it when none of its tets is taken. The
// max-heap is a sorted array: every candidate is popped anyway.
#include "hex/tet_to_hex_internal.h"
#include "common/parallel.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace femorph {
namespace tet_to_hex {
namespace {

/// A double's bits as an unsigned integer of the same order.
std::uint64_t ordered_bits(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return (bits >> 63) ? ~bits : bits | (std::uint64_t(1) << 63);
}

struct Key {
  std::uint64_t key;  // ascending = decreasing priority
  index_t index;
};

/// Stable LSD radix sort of keys by `key`, 11 bits a pass; each pass splits
/// the keys into blocks counted and scattered in parallel, in block order.
void radix_sort(std::vector<Key>& keys) {
  constexpr int kBits = 11, kBuckets = 1 << kBits, kBlocks = 8;
  const std::size_t n = keys.size();
  std::vector<Key> other(n);
  std::vector<std::size_t> counts(static_cast<std::size_t>(kBlocks) * kBuckets);
  std::size_t bounds[kBlocks + 1];
  for (int b = 0; b <= kBlocks; ++b) bounds[b] = n * b / kBlocks;
  const bool parallel = n >= static_cast<std::size_t>(kParallelMinItems);
  for (int shift = 0; shift < 64; shift += kBits) {
    std::fill(counts.begin(), counts.end(), 0);
    parallel_for_chunks(
        static_cast<long>(kBlocks),
        [&](long begin, long end, int) {
          for (int b = static_cast<int>(begin); b < static_cast<int>(end); ++b)
            for (std::size_t i = bounds[b]; i < bounds[b + 1]; ++i)
              ++counts[b * kBuckets + ((keys[i].key >> shift) & (kBuckets - 1))];
        },
        parallel_when(parallel), 1);
    // Offsets: bucket-major, then block order (stability).
    std::size_t sum = 0;
    for (int d = 0; d < kBuckets; ++d)
      for (int b = 0; b < kBlocks; ++b) {
        const std::size_t c = counts[b * kBuckets + d];
        counts[b * kBuckets + d] = sum;
        sum += c;
      }
    parallel_for_chunks(
        static_cast<long>(kBlocks),
        [&](long begin, long end, int) {
          for (int b = static_cast<int>(begin); b < static_cast<int>(end); ++b)
            for (std::size_t i = bounds[b]; i < bounds[b + 1]; ++i)
              other[counts[b * kBuckets + ((keys[i].key >> shift) & (kBuckets - 1))]++] = keys[i];
        },
        parallel_when(parallel), 1);
    keys.swap(other);
  }
}

}  // namespace

void sort_candidates(std::vector<Candidate>& candidates) {
  // search_candidates lists them by their sorted tets; a stable sort by
  // priority keeps that order among equal priorities.
  const std::size_t n = candidates.size();
  std::vector<Key> keys(n);
  for (std::size_t i = 0; i < n; ++i)
    keys[i] = { ~ordered_bits(candidates[i].priority), static_cast<index_t>(i) };
  radix_sort(keys);
  std::vector<Candidate> sorted(n);
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
  parallel_for_chunks(
      static_cast<long>(count),
      [&](long begin, long end, int) {
        for (std::ptrdiff_t i = static_cast<std::ptrdiff_t>(begin); i < static_cast<std::ptrdiff_t>(end); ++i)
          sorted[i] = candidates[keys[i].index];
      },
      kParallelMinItems);
  candidates.swap(sorted);
}

void adopt_candidates_greedy(const std::vector<Candidate>& candidates,
                             const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                             const std::vector<index_t>& adjacency, std::vector<Cell>& cells,
                             std::vector<index_t>& cell_of_tet) {
  cell_of_tet.assign(tets.size(), kInvalidIndex);
  std::vector<index_t> adopted;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Candidate& c = candidates[i];
    bool free = true;
    for (int k = 0; k < c.num_tets && free; ++k) free = cell_of_tet[c.tets[k]] == kInvalidIndex;
    if (!free) continue;
    for (int k = 0; k < c.num_tets; ++k) cell_of_tet[c.tets[k]] = static_cast<index_t>(adopted.size());
    adopted.push_back(static_cast<index_t>(i));
  }
  // The adopted cells' nodes, replaying their walks.
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(adopted.size());
  cells.assign(adopted.size(), Cell());
  parallel_for_chunks(
      static_cast<long>(n),
      [&](long begin, long end, int) {
        for (std::ptrdiff_t i = static_cast<std::ptrdiff_t>(begin); i < static_cast<std::ptrdiff_t>(end); ++i)
          cells[i] = candidate_cell(candidates[adopted[i]], adopted[i], points, tets, adjacency);
      },
      kParallelMinItems);
}

}  // namespace tet_to_hex
}  // namespace femorph
