#include "mesh/unique_edges.h"
#include "common/parallel.h"

#include "mesh/tet_mesh.h"

#include <vector>
#include <algorithm>

namespace femorph {

namespace {

/// tet(t) gives tet t of [0, num_tets) or nullptr for a dead slot; keep(a,
/// b) filters edges. In parallel: each edge (a < b) goes into a's bucket,
/// the buckets are deduplicated and sorted per thread, and the result is
/// in (a, b) order whatever the number of threads.
template <class TetAt, class Keep>
std::vector<Edge> bucket_edges(index_t num_vertices, long num_tets, TetAt&& tet, Keep&& keep) {
  const std::size_t nv = static_cast<std::size_t>(std::max<index_t>(num_vertices, 0));
  const long min_items = parallel_when(num_tets >= kParallelMinItems);
  // fn(a, b) for every kept edge (a < b) of every tet, tets in parallel.
  const auto each_edge = [&](auto&& fn) {
    parallel_for(
        num_tets,
        [&](long t) {
          const Tet* T = tet(t);
          if (!T) return;
          for (const auto& e : kTetEdge) {
            const index_t a = std::min((*T)[e[0]], (*T)[e[1]]), b = std::max((*T)[e[0]], (*T)[e[1]]);
            if (keep(a, b)) fn(a, b);
          }
        },
        min_items);
  };
  std::vector<index_t> start(nv + 1, 0);
  each_edge([&](index_t a, index_t) { fetch_add(start[static_cast<std::size_t>(a) + 1], index_t(1)); });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<index_t> other(static_cast<std::size_t>(start[nv]));
  {
    std::vector<index_t> fill(start.begin(), start.end() - 1);
    each_edge([&](index_t a, index_t b) {
      other[static_cast<std::size_t>(fetch_add(fill[static_cast<std::size_t>(a)], index_t(1)))] = b;
    });
  }
  // Each edge is listed once per tet holding it (about five times): drop
  // the repeats with a mark per vertex before sorting the few that remain.
  std::vector<index_t> unique_count(nv + 1, 0);
  std::vector<std::vector<index_t>> seen_by(static_cast<std::size_t>(parallel_threads()));
  parallel_for_worker(
      static_cast<long>(nv),
      [&](long ai, int worker) {
        std::vector<index_t>& seen = seen_by[static_cast<std::size_t>(worker)];
        if (seen.empty()) seen.assign(nv, kInvalidIndex);
        const std::size_t a = static_cast<std::size_t>(ai);
        auto first = other.begin() + start[a], last = first;
        for (auto it = first; it != other.begin() + start[a + 1]; ++it)
          if (seen[static_cast<std::size_t>(*it)] != static_cast<index_t>(a)) {
            seen[static_cast<std::size_t>(*it)] = static_cast<index_t>(a);
            *last++ = *it;
          }
        std::sort(first, last);
        unique_count[a + 1] = static_cast<index_t>(last - first);
      },
      min_items, 4096);
  for (std::size_t v = 0; v < nv; ++v) unique_count[v + 1] += unique_count[v];
  std::vector<Edge> edges(static_cast<std::size_t>(unique_count[nv]));
  parallel_for(
      static_cast<long>(nv),
      [&](long ai) {
        const std::size_t a = static_cast<std::size_t>(ai);
        for (index_t k = 0; k < unique_count[a + 1] - unique_count[a]; ++k)
          edges[static_cast<std::size_t>(unique_count[a] + k)] =
              Edge(static_cast<index_t>(a), other[static_cast<std::size_t>(start[a] + k)]);
      },
      min_items, 4096);
  return edges;
}

}  // namespace

std::vector<Edge> unique_edges(const std::vector<Tet>& tets, index_t num_vertices) {
  return bucket_edges(
      num_vertices, static_cast<long>(tets.size()),
      [&](long t) { return tets[static_cast<std::size_t>(t)][0] >= 0 ? &tets[static_cast<std::size_t>(t)] : nullptr; },
      [](index_t, index_t) { return true; });
}

std::vector<Edge> unique_edges(const TetMesh& mesh, const std::vector<char>* mask) {
  const auto flagged = [mask](index_t v) {
    return !mask || mask->empty() || (static_cast<std::size_t>(v) < mask->size() && (*mask)[v]);
  };
  return bucket_edges(
      mesh.vertex_slots(), static_cast<long>(mesh.tet_slots()),
      [&](long t) { return mesh.tet_alive(static_cast<index_t>(t)) ? &mesh.tet(static_cast<index_t>(t)) : nullptr; },
      [&](index_t a, index_t b) { return flagged(a) && flagged(b); });
}

}  // namespace femorph
