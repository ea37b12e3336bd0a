#include "improve/optimize_worst_vertices.h"

#include "common/parallel.h"
#include "improve/ball_quality.h"
#include "improve/coloured_balls.h"
#include "improve/scan_live_tets.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <vector>

namespace femorph {

namespace {

/// compass_search_vertex with v's ball given (every live tet that holds v):
/// touches no shared scratch, so it may run concurrently for vertices that
/// share no tet.
double compass_search_in_ball(TetMesh& mesh, index_t v, const std::vector<index_t>& ball,
                              std::vector<index_t>& neighbours) {
  neighbours.clear();
  for (const index_t t : ball)
    for (const index_t w : mesh.tet(t))
      if (w != v) neighbours.push_back(w);
  Vec3 x = mesh.point(v);
  MovingBall moving(mesh, ball, v);
  double start;
  const double best = compass_search(moving, compass_start_step(mesh, neighbours, x), &x, &start);
  // Stretch > 0 means positive volume, but the exact test decides.
  if (best > start && mesh.move_vertex_in_ball(v, x, ball) == OpStatus::Ok) return best;
  return start;
}

}  // namespace

double compass_start_step(const TetMesh& mesh, std::vector<index_t>& neighbours, const Vec3& x) {
  std::sort(neighbours.begin(), neighbours.end());
  neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
  double len = 0;
  for (const index_t w : neighbours) len += (mesh.point(w) - x).norm();
  return 0.25 * len / static_cast<double>(std::max<std::size_t>(1, neighbours.size()));
}

double compass_search(MovingBall& ball, double step, Vec3* x, double* start_min) {
  double best = ball.min_stretch(*x);
  if (start_min) *start_min = best;
  for (int halving = 0; halving < 10; ++halving, step *= 0.5) {
    bool moved = true;
    while (moved) {
      moved = false;
      for (int d = 0; d < 6; ++d) {
        Vec3 y = *x;
        y[d / 2] += d % 2 ? -step : step;
        double q;
        if (ball.exceeds(y, best, &q)) {
          best = q;
          *x = y;
          moved = true;
        }
      }
    }
  }
  return best;
}

double compass_search_vertex(TetMesh& mesh, index_t v) {
  thread_local std::vector<index_t> ball, neighbours;
  mesh.vertex_ball(v, ball);
  return compass_search_in_ball(mesh, v, ball, neighbours);
}

WorstVertexStats optimize_worst_vertices(TetMesh& mesh, const WorstVertexOptions& options) {
  WorstVertexStats stats;
  std::vector<index_t> candidates;
  std::vector<std::uint8_t> mask;
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
      if (std::none_of(T.begin(), T.end(), movable) ||  // first: the cheaper test
          tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3])) >= options.threshold)
        return;
      for (const index_t v : T)
        if (movable(v)) out.push_back(v);
    });
    join_chunks(found, [](const std::vector<index_t>& f) -> const std::vector<index_t>& { return f; }, &candidates);
    if (candidates.empty()) break;
    // Coloured (vertices of one colour share no tet) and searched colour by
    // colour, each colour in parallel: the same moves for any number of
    // threads.
    mask.assign(static_cast<std::size_t>(mesh.vertex_slots()), 0);
    for (const index_t v : candidates) mask[v] = 1;
    const ColouredBalls cb = coloured_balls(mesh, mask);
    std::size_t improved = 0;
    for (std::size_t c = 0; c + 1 < cb.colour_start.size(); ++c) {
      const long first = static_cast<long>(cb.colour_start[c]), last = static_cast<long>(cb.colour_start[c + 1]);
      improved += parallel_reduce(
          last - first, std::size_t(0),
          [&](long begin, long end, int) {
            std::vector<index_t> ball, neighbours;
            std::size_t k = 0;
            for (long j = first + begin; j < first + end; ++j) {
              const index_t v = cb.vertices[static_cast<std::size_t>(j)];
              const std::size_t b = cb.ball_start[static_cast<std::size_t>(j)],
                                e = cb.ball_start[static_cast<std::size_t>(j) + 1];
              ball.assign(cb.ball_tets.begin() + static_cast<std::ptrdiff_t>(b),
                          cb.ball_tets.begin() + static_cast<std::ptrdiff_t>(e));
              const Vec3 before = mesh.point(v);
              compass_search_in_ball(mesh, v, ball, neighbours);
              k += mesh.point(v) != before;
            }
            return k;
          },
          std::plus<std::size_t>(), 64, 16);
    }
    stats.candidates += cb.vertices.size();
    stats.improved += improved;
    if (improved == 0) break;
  }
  return stats;
}

}  // namespace femorph
