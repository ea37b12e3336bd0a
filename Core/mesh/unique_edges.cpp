#include "mesh/unique_edges.h"

#include "mesh/tet_mesh.h"

#include <algorithm>

namespace femorph {

namespace {

constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

/// for_each_tet(fn) calls fn(const Tet&) for every tet to count; keep(a, b)
/// filters edges.
template <class ForEachTet, class Keep>
std::vector<Edge> bucket_edges(index_t num_vertices, ForEachTet&& for_each_tet, Keep&& keep) {
  const std::size_t nv = static_cast<std::size_t>(std::max<index_t>(num_vertices, 0));
  std::vector<index_t> start(nv + 1, 0);
  for_each_tet([&](const Tet& T) {
    for (const auto& e : kTetEdges) {
      const index_t a = std::min(T[e[0]], T[e[1]]), b = std::max(T[e[0]], T[e[1]]);
      if (keep(a, b)) ++start[static_cast<std::size_t>(a) + 1];
    }
  });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<index_t> other(static_cast<std::size_t>(start[nv]));
  std::vector<index_t> fill(start.begin(), start.end() - 1);
  for_each_tet([&](const Tet& T) {
    for (const auto& e : kTetEdges) {
      const index_t a = std::min(T[e[0]], T[e[1]]), b = std::max(T[e[0]], T[e[1]]);
      if (keep(a, b)) other[static_cast<std::size_t>(fill[a]++)] = b;
    }
  });
  // Each edge is listed once per tet holding it (about five times): drop
  // the repeats with a mark per vertex before sorting the few that remain.
  std::vector<Edge> edges;
  edges.reserve(other.size() / 4);
  std::vector<index_t> seen(nv, kInvalidIndex);
  for (std::size_t a = 0; a < nv; ++a) {
    auto first = other.begin() + start[a], last = first;
    for (auto it = first; it != other.begin() + start[a + 1]; ++it)
      if (seen[static_cast<std::size_t>(*it)] != static_cast<index_t>(a)) {
        seen[static_cast<std::size_t>(*it)] = static_cast<index_t>(a);
        *last++ = *it;
      }
    std::sort(first, last);
    for (auto it = first; it != last; ++it) edges.emplace_back(static_cast<index_t>(a), *it);
  }
  return edges;
}

}  // namespace

std::vector<Edge> unique_edges(const std::vector<Tet>& tets, index_t num_vertices) {
  return bucket_edges(
      num_vertices,
      [&](auto&& fn) {
        for (const Tet& T : tets)
          if (T[0] >= 0) fn(T);
      },
      [](index_t, index_t) { return true; });
}

std::vector<Edge> unique_edges(const TetMesh& mesh, const std::vector<char>* mask) {
  const auto flagged = [mask](index_t v) {
    return !mask || mask->empty() || (static_cast<std::size_t>(v) < mask->size() && (*mask)[v]);
  };
  return bucket_edges(
      mesh.vertex_slots(),
      [&](auto&& fn) {
        for (index_t t = 0; t < mesh.tet_slots(); ++t)
          if (mesh.tet_alive(t)) fn(mesh.tet(t));
      },
      [&](index_t a, index_t b) { return flagged(a) && flagged(b); });
}

}  // namespace femorph
