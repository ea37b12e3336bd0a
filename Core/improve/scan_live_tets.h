// A parallel scan of every live tet whose result does not depend on the
// number of threads: the shared loop of Improve's full-mesh scans (the
// stretch range, the density heaps' edges, the degenerate heap, the worst
// vertices).
#pragma once

#include "common/parallel.h"
#include "common/types.h"
#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace femorph {

/// Tet slots per chunk: large enough that a chunk's work outweighs its
/// scheduling, small enough for two threads to share the load.
constexpr long kTetScanChunk = 8192;

/// Calls fn(t, acc) for every live tet t, in slot order within fixed chunks
/// of kTetScanChunk slots; each chunk has its own Acc (value-initialised by
/// `init`). The chunks run in parallel and are returned in slot order, so
/// whatever the caller combines from them in that order is the same for any
/// number of threads.
template <class Acc, class Fn>
std::vector<Acc> scan_live_tets(const TetMesh& mesh, const Acc& init, Fn&& fn) {
  const long slots = mesh.tet_slots();
  const long chunks = (slots + kTetScanChunk - 1) / kTetScanChunk;
  std::vector<Acc> acc(static_cast<std::size_t>(chunks), init);
  parallel_for_chunks(
      slots,
      [&](long begin, long end, int) {
        Acc& a = acc[static_cast<std::size_t>(begin / kTetScanChunk)];
        for (long k = begin; k < end; ++k) {
          const index_t t = static_cast<index_t>(k);
          if (mesh.tet_alive(t)) fn(t, a);
        }
      },
      kParallelMinItems, kTetScanChunk);
  return acc;
}

/// The items each chunk of scan_live_tets found (items(chunk) gives them),
/// joined in slot order into *out, which keeps its capacity.
template <class T, class Chunk, class Items>
void join_chunks(const std::vector<Chunk>& chunks, Items&& items, std::vector<T>* out) {
  std::size_t total = 0;
  for (const Chunk& c : chunks) total += items(c).size();
  out->clear();
  out->reserve(total);
  for (const Chunk& c : chunks) out->insert(out->end(), items(c).begin(), items(c).end());
}

}  // namespace femorph
