#include "improve/split_locked_tets.h"

#include "common/parallel.h"
#include "improve/ball_quality.h"
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

/// The live tet with the vertices of T (tried first at `slot`), or -1.
/// (A face of T does not tell: the tet across it has the face too.)
index_t find_tet(const TetMesh& mesh, const Tet& T, index_t slot, std::vector<index_t>& ball) {
  if (mesh.tet_alive(slot) && mesh.tet(slot) == T) return slot;
  if (!mesh.vertex_alive(T[0])) return kInvalidIndex;
  mesh.vertex_ball(T[0], ball);
  for (const index_t t : ball)
    if (mesh.local_index(t, T[1]) >= 0 && mesh.local_index(t, T[2]) >= 0 && mesh.local_index(t, T[3]) >= 0) return t;
  return kInvalidIndex;
}

/// A tet below the threshold (at `slot` when its batch began) and what
/// evaluate_locked_tet found for it.
struct LockedTet {
  index_t slot = kInvalidIndex;  ///< where the scan found it
  Tet tet{};
  bool split = false;      ///< an edge to split was found
  index_t a = kInvalidIndex, b = kInvalidIndex;
  Vec3 x = Vec3::Zero();                  ///< the new vertex's position
  double before = 0, at_midpoint = 0;     ///< the ring's minimum stretch, the new ball's at the midpoint
  std::vector<index_t> ring, opposite;    ///< of (a, b), as edge_ring_with_vertices lists them
  std::vector<index_t> read;              ///< vertices whose tets the evaluation read
};

/// Read only (so tets can be evaluated in parallel): the interior edges of
/// tet `t` (slot; e.tet its vertices), longest first; the first whose split
/// at the midpoint, with the new vertex then moved by compass search, has a
/// ball whose minimum stretch beats the worst tet around the edge now. The
/// mesh is not changed: the new vertex's ball is the edge's ring split in
/// two (MovingBall's split constructor).
void evaluate_locked_tet(const TetMesh& mesh, index_t t, LockedTet& e) {
  const Tet& T = e.tet;
  e.split = false;
  e.read.assign(T.begin(), T.end());
  // The interior edges with their rings (walked once), longest first.
  struct InnerEdge {
    double length;
    index_t a, b;
    std::vector<index_t> ring, opposite;
  };
  thread_local std::vector<InnerEdge> edges(6);
  thread_local std::vector<index_t> neighbours;
  int count = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      InnerEdge& edge = edges[static_cast<std::size_t>(count)];
      bool boundary = true;
      if (!mesh.edge_ring_with_vertices(T[i], T[j], edge.ring, edge.opposite, &boundary, t) || boundary) continue;
      edge.length = (mesh.point(T[i]) - mesh.point(T[j])).norm();
      edge.a = T[i];
      edge.b = T[j];
      ++count;
    }
  // Stable, as the pairs (-length, (i, j)) sorted before.
  std::stable_sort(edges.begin(), edges.begin() + count,
                   [](const InnerEdge& x, const InnerEdge& y) { return x.length > y.length; });
  for (int k = 0; k < count; ++k) {
    const InnerEdge& edge = edges[static_cast<std::size_t>(k)];
    e.read.insert(e.read.end(), edge.opposite.begin(), edge.opposite.end());
    const double before = min_stretch(mesh, edge.ring);
    Vec3 x = 0.5 * (mesh.point(edge.a) + mesh.point(edge.b));
    neighbours.assign(edge.opposite.begin(), edge.opposite.end());
    neighbours.push_back(edge.a);
    neighbours.push_back(edge.b);
    MovingBall ball(mesh, edge.ring, edge.a, edge.b, x);
    if (compass_search(ball, compass_start_step(mesh, neighbours, x), &x, &e.at_midpoint) > before) {
      e.split = true;
      e.before = before;
      e.a = edge.a;
      e.b = edge.b;
      e.x = x;
      e.ring = edge.ring;
      e.opposite = edge.opposite;
      return;
    }
  }
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
  using Entry = std::pair<double, std::pair<Tet, index_t>>;
  const std::vector<std::vector<Entry>> found = scan_live_tets(mesh, std::vector<Entry>{},
                                                               [&](index_t t, std::vector<Entry>& out) {
    const Tet& T = mesh.tet(t);
    for (const index_t v : T)
      if ((options.only_locked && !mesh.on_boundary(v)) || !flagged(v)) return;
    const double q = stretch_of(mesh, t);
    if (q < options.threshold) out.push_back({q, {T, t}});
  });
  std::vector<Entry> locked;
  join_chunks(found, [](const std::vector<Entry>& f) -> const std::vector<Entry>& { return f; }, &locked);
  std::sort(locked.begin(), locked.end());
  stats.locked = locked.size();

  // Beyond the thesis: the tets are evaluated in batches in parallel (read
  // only) and split in order; a tet whose evaluation read a vertex that an
  // earlier split of its batch changed goes into the next batch, in front.
  // The batches do not depend on the number of threads, so neither does
  // the result.
  constexpr std::size_t kBatch = 256;
  std::vector<LockedTet> batch(kBatch);
  std::vector<std::size_t> ids, deferred;  // into `locked`
  std::vector<std::uint32_t> changed;  // batch id per vertex a split of that batch changed
  std::uint32_t batch_id = 0;
  std::vector<index_t> ball;
  for (std::size_t next = 0; next < locked.size() || !deferred.empty();) {
    ids.clear();
    // The tets still there (an earlier split may have taken them), at
    // their slot now.
    std::size_t n = 0;
    const auto take = [&](std::size_t id) {
      LockedTet& e = batch[n];
      e.tet = locked[id].second.first;
      e.slot = find_tet(mesh, e.tet, locked[id].second.second, ball);
      if (e.slot < 0) return;
      locked[id].second.second = e.slot;
      ids.push_back(id);
      ++n;
    };
    std::size_t d = 0;
    for (; d < deferred.size() && n < kBatch; ++d) take(deferred[d]);
    deferred.erase(deferred.begin(), deferred.begin() + static_cast<std::ptrdiff_t>(d));
    for (; next < locked.size() && n < kBatch; ++next) take(next);
    const long count = static_cast<long>(n);
    parallel_for(
        count,
        [&](long i) {
          LockedTet& e = batch[static_cast<std::size_t>(i)];
          evaluate_locked_tet(mesh, e.slot, e);
        },
        32, 4);
    ++batch_id;
    const auto untouched = [&](index_t w) {
      return static_cast<std::size_t>(w) >= changed.size() || changed[static_cast<std::size_t>(w)] != batch_id;
    };
    for (std::size_t i = 0; i < n; ++i) {
      LockedTet& e = batch[i];
      if (!std::all_of(e.read.begin(), e.read.end(), untouched)) {
        deferred.push_back(ids[i]);  // evaluated on a mesh that has changed since
        continue;
      }
      if (!e.split) continue;
      // The tets around (a, b) change: nothing else does (the new vertex
      // is new).
      if (changed.size() < static_cast<std::size_t>(mesh.vertex_slots()) + 1)
        changed.resize(static_cast<std::size_t>(mesh.vertex_slots()) + 1, 0);
      changed[static_cast<std::size_t>(e.a)] = changed[static_cast<std::size_t>(e.b)] = batch_id;
      // Split at the midpoint, then moved where the search found (the exact
      // test decides, as for any move).
      index_t v = kInvalidIndex;
      if (mesh.split_edge(e.a, e.b, nullptr, &v, e.ring, e.opposite, false) != OpStatus::Ok) continue;
      mesh.vertex_ball(v, ball);
      if (mesh.move_vertex_in_ball(v, e.x, ball) == OpStatus::Ok || e.at_midpoint > e.before)
        ++stats.splits;
      else
        mesh.half_edge_collapse(Keep{e.a}, Remove{v});  // undo: the tets around (a, b) come back
    }
  }
  return stats;
}

}  // namespace femorph
