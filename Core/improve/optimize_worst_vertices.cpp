#include "improve/optimize_worst_vertices.h"

#include "improve/ball_quality.h"
#include "improve/scan_live_tets.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace femorph {

double compass_search_vertex(TetMesh& mesh, index_t v) {
  thread_local std::vector<index_t> ball, neighbours;
  mesh.vertex_ball(v, ball);
  mesh.vertex_neighbors(v, neighbours);
  Vec3 x = mesh.point(v);
  double len = 0;
  for (const index_t w : neighbours) len += (mesh.point(w) - x).norm();
  double step = 0.25 * len / static_cast<double>(std::max<std::size_t>(1, neighbours.size()));
  MovingBall moving(mesh, ball, v);
  const double start = moving.min_stretch(x);
  double best = start;
  for (int halving = 0; halving < 10; ++halving, step *= 0.5) {
    bool moved = true;
    while (moved) {
      moved = false;
      for (int d = 0; d < 6; ++d) {
        Vec3 y = x;
        y[d / 2] += d % 2 ? -step : step;
        double q;
        if (moving.exceeds(y, best, &q)) {
          best = q;
          x = y;
          moved = true;
        }
      }
    }
  }
  // Stretch > 0 means positive volume, but the exact test decides.
  if (best > start && mesh.move_vertex(v, x) == OpStatus::Ok) return best;
  return start;
}

WorstVertexStats optimize_worst_vertices(TetMesh& mesh, const WorstVertexOptions& options) {
  WorstVertexStats stats;
  std::vector<index_t> candidates;
  const auto movable = [&](index_t v) {
    return mesh.vertex_class(v) == VertexClass::Inner &&
           (options.vertex_mask.empty() ||
            (static_cast<std::size_t>(v) < options.vertex_mask.size() && options.vertex_mask[v]));
  };
  for (int pass = 0; pass < options.passes; ++pass) {
    // The vertices of the tets below the threshold, found in parallel
    // (sorted below, so the order found does not matter).
    const auto found = scan_live_tets(mesh, std::vector<index_t>{}, [&](index_t t, std::vector<index_t>& out) {
      const Tet& T = mesh.tet(t);
      if (tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3])) >= options.threshold)
        return;
      for (const index_t v : T)
        if (movable(v)) out.push_back(v);
    });
    join_chunks(found, [](const std::vector<index_t>& f) -> const std::vector<index_t>& { return f; }, &candidates);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    if (candidates.empty()) break;
    std::size_t improved = 0;
    for (const index_t v : candidates) {
      ++stats.candidates;
      const Vec3 before = mesh.point(v);
      compass_search_vertex(mesh, v);
      if (mesh.point(v) != before) {
        ++stats.improved;
        ++improved;
      }
    }
    if (improved == 0) break;
  }
  return stats;
}

}  // namespace femorph
