#include "mesh/unique_edges.h"

#include "mesh/tet_mesh.h"

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
  const bool parallel = num_tets >= kParallelMinItems;
  // fn(a, b) for every kept edge (a < b) of every tet, tets in parallel.
  const auto each_edge = [&](auto&& fn) {
#pragma omp parallel for schedule(static) if (parallel)
    for (long t = 0; t < num_tets; ++t) {
      const Tet* T = tet(t);
      if (!T) continue;
      for (const auto& e : kTetEdge) {
        const index_t a = std::min((*T)[e[0]], (*T)[e[1]]), b = std::max((*T)[e[0]], (*T)[e[1]]);
        if (keep(a, b)) fn(a, b);
      }
    }
  };
  std::vector<index_t> start(nv + 1, 0);
  each_edge([&](index_t a, index_t) {
#pragma omp atomic
    ++start[static_cast<std::size_t>(a) + 1];
  });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<index_t> other(static_cast<std::size_t>(start[nv]));
  {
    std::vector<index_t> fill(start.begin(), start.end() - 1);
    each_edge([&](index_t a, index_t b) {
      index_t slot;
#pragma omp atomic capture
      slot = fill[static_cast<std::size_t>(a)]++;
      other[static_cast<std::size_t>(slot)] = b;
    });
  }
  // Each edge is listed once per tet holding it (about five times): drop
  // the repeats with a mark per vertex before sorting the few that remain.
  std::vector<index_t> unique_count(nv + 1, 0);
#pragma omp parallel if (parallel)
  {
    std::vector<index_t> seen(nv, kInvalidIndex);
#pragma omp for schedule(dynamic, 4096)
    for (std::size_t a = 0; a < nv; ++a) {
      auto first = other.begin() + start[a], last = first;
      for (auto it = first; it != other.begin() + start[a + 1]; ++it)
        if (seen[static_cast<std::size_t>(*it)] != static_cast<index_t>(a)) {
          seen[static_cast<std::size_t>(*it)] = static_cast<index_t>(a);
          *last++ = *it;
        }
      std::sort(first, last);
      unique_count[a + 1] = static_cast<index_t>(last - first);
    }
  }
  for (std::size_t v = 0; v < nv; ++v) unique_count[v + 1] += unique_count[v];
  std::vector<Edge> edges(static_cast<std::size_t>(unique_count[nv]));
#pragma omp parallel for schedule(dynamic, 4096) if (parallel)
  for (std::size_t a = 0; a < nv; ++a)
    for (index_t k = 0; k < unique_count[a + 1] - unique_count[a]; ++k)
      edges[static_cast<std::size_t>(unique_count[a] + k)] = Edge(static_cast<index_t>(a), other[static_cast<std::size_t>(start[a] + k)]);
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
