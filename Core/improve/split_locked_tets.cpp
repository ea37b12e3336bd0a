#include "improve/split_locked_tets.h"

#include "improve/optimize_worst_vertices.h"
#include "improve/scan_live_tets.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace femorph {

namespace {

double stretch_of(const TetMesh& mesh, index_t t) {
  const Tet& T = mesh.tet(t);
  return tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]));
}

double min_stretch(const TetMesh& mesh, const std::vector<index_t>& tets) {
  double q = std::numeric_limits<double>::infinity();
  for (const index_t t : tets) q = std::min(q, stretch_of(mesh, t));
  return q;
}

}  // namespace

LockedTetStats split_locked_tets(TetMesh& mesh, const LockedTetOptions& options) {
  LockedTetStats stats;
  const auto flagged = [&](index_t v) {
    return options.vertex_mask.empty() ||
           (static_cast<std::size_t>(v) < options.vertex_mask.size() && options.vertex_mask[v]);
  };
  // The locked tets, worst first (tets are re-checked when their turn comes).
  // Found in parallel (read only); the sort makes the order independent of
  // the threads.
  using Entry = std::pair<double, Tet>;
  const std::vector<std::vector<Entry>> found = scan_live_tets(mesh, std::vector<Entry>{},
                                                               [&](index_t t, std::vector<Entry>& out) {
    const Tet& T = mesh.tet(t);
    for (const index_t v : T)
      if ((options.only_locked && !mesh.on_boundary(v)) || !flagged(v)) return;
    const double q = stretch_of(mesh, t);
    if (q < options.threshold) out.emplace_back(q, T);
  });
  std::vector<Entry> locked;
  join_chunks(found, [](const std::vector<Entry>& f) -> const std::vector<Entry>& { return f; }, &locked);
  std::sort(locked.begin(), locked.end());
  stats.locked = locked.size();

  std::vector<index_t> ring, ball;
  for (const auto& entry : locked) {
    const Tet& T = entry.second;
    // Still there (an earlier split may have removed it)?
    const index_t t = mesh.find_face(T[0], T[1], T[2]);
    if (t < 0 || mesh.local_index(t, T[3]) < 0) continue;
    // Its interior edges, longest first.
    std::vector<std::pair<double, std::pair<index_t, index_t>>> edges;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        bool boundary = true;
        if (!mesh.edge_ring(T[i], T[j], ring, &boundary, t) || boundary) continue;
        edges.push_back({-(mesh.point(T[i]) - mesh.point(T[j])).norm(), {T[i], T[j]}});
      }
    std::sort(edges.begin(), edges.end());
    for (const auto& edge : edges) {
      const index_t a = edge.second.first, b = edge.second.second;
      bool boundary = true;
      if (!mesh.edge_ring(a, b, ring, &boundary) || boundary) continue;
      const double before = min_stretch(mesh, ring);
      index_t v = kInvalidIndex;
      if (mesh.split_edge(a, b, nullptr, &v, ring.front()) != OpStatus::Ok) continue;
      if (compass_search_vertex(mesh, v) > before) {
        ++stats.splits;
        break;
      }
      mesh.half_edge_collapse(v, a);  // undo: the tets around (a, b) come back
    }
  }
  return stats;
}

}  // namespace femorph
