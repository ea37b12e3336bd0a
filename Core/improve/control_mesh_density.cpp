// Mesh density control, thesis 2.6.3 Fig. 2.40 (c); see control_mesh_density.h.
#include "improve/control_mesh_density.h"

#include "common/parallel.h"
#include "improve/ball_quality.h"
#include "improve/edge_queue.h"
#include "improve/scan_live_tets.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace femorph {

namespace {

bool masked(const std::vector<char>& mask, index_t v) {
  return mask.empty() || (static_cast<std::size_t>(v) < mask.size() && mask[v]);
}

/// DensityControlOptions::touched.
void touch(std::vector<char>* touched, index_t v) {
  if (!touched) return;
  if (static_cast<std::size_t>(v) >= touched->size()) touched->resize(static_cast<std::size_t>(v) + 1, 0);
  (*touched)[static_cast<std::size_t>(v)] = 1;
}

/// L(e) * rho_GC(c_e); 0 where the field has no density.
double scaled_length(const TetMesh& mesh, const DensityGrid& grid, DensityLookup lookup, index_t a, index_t b,
                     double* length) {
  const Vec3& p = mesh.point(a);
  const Vec3& q = mesh.point(b);
  *length = (q - p).norm();
  return *length * grid.density_at(0.5 * (p + q), lookup);
}

/// Sorts heap entries by ends and drops the repeats.
void sort_unique_by_ends(std::vector<HeapEdge>& edges) {
  const auto by_ends = [](const HeapEdge& x, const HeapEdge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; };
  std::sort(edges.begin(), edges.end(), by_ends);
  edges.erase(std::unique(edges.begin(), edges.end(),
                          [](const HeapEdge& x, const HeapEdge& y) { return x.a == y.a && x.b == y.b; }),
              edges.end());
}

/// The masked edges (a < b) with scaled length >= beta1 into *longs and
/// with 0 < scaled length <= beta2 into *shorts (either may be null), each
/// once and sorted by ends, as heap entries (steps 1 and 4). Found tet by
/// tet in parallel: few edges pass, so the full edge list is not built; an
/// edge is met once per tet holding it and the repeats are dropped after
/// sorting.
void edges_passing(const TetMesh& mesh, const DensityGrid& grid, DensityLookup lookup, const std::vector<char>& mask,
                   double beta1, double beta2, std::vector<HeapEdge>* longs, std::vector<HeapEdge>* shorts,
                   bool longs_unmasked = false) {
  struct Found {
    std::vector<HeapEdge> longs, shorts;
  };
  const std::vector<Found> found = scan_live_tets(mesh, Found{}, [&](index_t t, Found& f) {
    const Tet& T = mesh.tet(t);
    for (const auto& e : kTetEdge) {
      const index_t a = std::min(T[e[0]], T[e[1]]), b = std::max(T[e[0]], T[e[1]]);
      const bool both = masked(mask, a) && masked(mask, b);
      if (!both && !longs_unmasked) continue;
      double length;
      const double s = scaled_length(mesh, grid, lookup, a, b, &length);
      if (longs && s >= beta1) f.longs.push_back({length, a, b, t});
      if (both && shorts && s > 0 && s <= beta2) f.shorts.push_back({length, a, b});
    }
  });
  if (longs) {
    join_chunks(found, [](const Found& f) -> const std::vector<HeapEdge>& { return f.longs; }, longs);
    sort_unique_by_ends(*longs);
  }
  if (shorts) {
    join_chunks(found, [](const Found& f) -> const std::vector<HeapEdge>& { return f.shorts; }, shorts);
    sort_unique_by_ends(*shorts);
  }
}

/// Stretch of tet t with vertex `from` renamed `to` and `moved` placed at
/// `position` (from/moved may be -1).
double stretch_with(const TetMesh& mesh, index_t t, index_t from, index_t to, index_t moved, const Vec3& position) {
  Vec3 p[4];
  for (int q = 0; q < 4; ++q) {
    index_t v = mesh.tet(t)[q];
    if (v == from) v = to;
    p[q] = v == moved ? position : mesh.point(v);
  }
  return tet_stretch(p[0], p[1], p[2], p[3]);
}

/// The stretch floor: refuse when the new worst tet is below the floor and
/// below the old worst.
bool below_floor(double new_min, double old_min, double floor) { return new_min < floor && new_min < old_min; }

/// The vertices of the tets of two balls except a and b, each once (in the
/// order met; `seen`: the caller's stamps per vertex slot): after the
/// collapse of a and b these are the neighbours of the surviving vertex.
void ball_vertices(const TetMesh& mesh, const std::vector<index_t>& ball_a, const std::vector<index_t>& ball_b,
                   index_t a, index_t b, TetMesh::VertexStamps& seen, std::vector<index_t>& out) {
  out.clear();
  const std::uint32_t stamp = seen.next(static_cast<std::size_t>(mesh.vertex_slots()));
  for (const std::vector<index_t>* ball : {&ball_a, &ball_b})
    for (const index_t t : *ball)
      for (const index_t w : mesh.tet(t))
        if (w != a && w != b && seen.stamp[w] != stamp) {
          seen.stamp[w] = stamp;
          out.push_back(w);
        }
}

enum class Projection { NotNeeded, Moved, Refused };

/// Moves the boundary vertex v to options.project(v, p) when that keeps its
/// ball valid and above the floor.
Projection try_project(TetMesh& mesh, index_t v, const DensityControlOptions& options, std::vector<index_t>& ball) {
  const Vec3 current = mesh.point(v);
  const Vec3 target = options.project(v, current);
  if (target == current) return Projection::NotNeeded;
  if (!target.allFinite()) return Projection::Refused;
  mesh.vertex_ball(v, ball);
  const double old_min = ball_min_stretch(mesh, ball, kInvalidIndex, current);
  const double new_min = ball_min_stretch(mesh, ball, v, target);
  if (below_floor(new_min, old_min, options.min_stretch)) return Projection::Refused;
  return mesh.move_vertex(v, target) == OpStatus::Ok ? Projection::Moved : Projection::Refused;
}

}  // namespace

namespace {

/// A split candidate popped from the heap and what its evaluation found.
struct SplitEval {
  HeapEdge entry{};
  bool is_edge = false, accepted = false, boundary = false;
  std::vector<index_t> ring, opposite;  // as edge_ring_with_vertices lists them
  // The split point m (the midpoint, or a third: split_in_thirds), and the
  // length and scaled length of (a, m) and (b, m): the parts the split pass
  // requeues when long, looked up in parallel.
  Vec3 point = Vec3::Zero();
  double half_length[2] = {0, 0}, half_scaled[2] = {0, 0};
  // The vertex the midpoint merges into (plan_merge), or kInvalidIndex, and
  // that vertex's new neighbours.
  index_t merge_into = kInvalidIndex;
  std::vector<index_t> merge_neighbours;
  std::vector<index_t> merge_ball;  // scratch: the ball of merge_into
};

/// Beyond the thesis: the merge of the inner midpoint m of a split into the
/// nearest vertex `into` of the edge's ring that this pass made (half-edge
/// collapse m -> into right after the split), when their scaled distance is
/// at most beta2. In a layer stretched across, the midpoints of two split
/// edges of one triangle lie half the third edge apart; left to the
/// collapse pass, they are most of the volume phase's first collapses.
/// Planned on the ring before the split, read only (in parallel; a
/// candidate whose ring an earlier split of its batch changed is requeued,
/// so the plan still holds when it is committed): every
/// ring tet (.. a .. b ..) becomes (b -> m) and (a -> m), and with m renamed
/// `into` those without `into` must stay at or above options.min_stretch,
/// no edge of `into` to the ring's vertices or the edge's ends may
/// become long (scaled length >= beta1), and none of the edges it makes may
/// exist already. Committed as one TetMesh::flip_edge_to_fan: the same mesh
/// without making and removing the midpoint in the serial part of the step.
void plan_merge(const TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                const std::vector<char>& made, const Vec3& m, TetMesh::WalkMarks& marks, SplitEval& e) {
  const index_t a = e.entry.a, b = e.entry.b;
  const auto made_here = [&made](index_t w) { return static_cast<std::size_t>(w) < made.size() && made[w]; };
  index_t into = kInvalidIndex;
  double best = options.collapse_threshold;
  for (const index_t w : e.opposite) {
    if (!made_here(w) || mesh.vertex_class(w) != VertexClass::Inner) continue;
    const Vec3& q = mesh.point(w);
    const double scaled = (q - m).norm() * grid.density_at(0.5 * (m + q), options.lookup);
    if (scaled > 0 && scaled <= best) {
      best = scaled;
      into = w;
    }
  }
  if (into == kInvalidIndex) return;
  for (const index_t t : e.ring) {
    const Tet& T = mesh.tet(t);
    if (std::find(T.begin(), T.end(), into) != T.end()) continue;  // goes with the edge
    if (stretch_with(mesh, t, b, into, kInvalidIndex, Vec3::Zero()) < options.min_stretch ||
        stretch_with(mesh, t, a, into, kInvalidIndex, Vec3::Zero()) < options.min_stretch)
      return;
  }
  std::vector<index_t>& neighbours = e.merge_neighbours;
  neighbours.clear();
  neighbours.push_back(a);
  neighbours.push_back(b);
  for (const index_t w : e.opposite)
    if (w != into && std::find(neighbours.begin(), neighbours.end(), w) == neighbours.end()) neighbours.push_back(w);
  for (const index_t w : neighbours) {
    double length;
    if (scaled_length(mesh, grid, options.lookup, into, w, &length) >= options.split_threshold) return;
  }
  // The link condition: no edge the merge makes (into to a ring vertex
  // not next to it) may exist already, outside the ring, nor, with three
  // ring tets, the face of the ring's vertices (a tet of into's ball with
  // both other ring vertices: the ring's own hold only one of them).
  std::vector<index_t>& ball = e.merge_ball;
  mesh.vertex_ball(into, ball, marks);
  const std::size_t n = e.opposite.size();
  const std::size_t k = static_cast<std::size_t>(std::find(e.opposite.begin(), e.opposite.end(), into) - e.opposite.begin());
  if (n == 3) {
    const index_t u = e.opposite[(k + 1) % 3], w = e.opposite[(k + 2) % 3];
    for (const index_t t : ball)
      if (mesh.local_index(t, u) >= 0 && mesh.local_index(t, w) >= 0) return;
  }
  for (std::size_t j = 0; j < n; ++j) {
    if (j == k || j == (k + 1) % n || (j + 1) % n == k) continue;
    const index_t w = e.opposite[j];
    for (const index_t t : ball)
      if (mesh.local_index(t, w) >= 0) return;
  }
  e.merge_into = into;
}

/// Steps 2-3 for one candidate without changing the mesh: its ring, and
/// whether the split keeps the stretch floor (every ring tet becomes two,
/// one with each end replaced by the midpoint). Read only, with the
/// caller's walk marks, so candidates can be evaluated in parallel.
void evaluate_split(const TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                    const std::vector<char>& made, TetMesh::WalkMarks& marks, SplitEval& e) {
  const index_t a = e.entry.a, b = e.entry.b;
  e.accepted = false;
  e.merge_into = kInvalidIndex;
  e.ring.clear();
  e.opposite.clear();
  const index_t t0 = mesh.find_edge_tet(a, b, e.entry.tag, marks);
  e.is_edge = t0 >= 0 && mesh.edge_ring_with_vertices(a, b, e.ring, e.opposite, &e.boundary, t0);
  if (!e.is_edge) return;
  // The split points to try: a third (split_in_thirds), then the midpoint
  // when the third's tets fall below the floor.
  const Vec3 mid = 0.5 * (mesh.point(a) + mesh.point(b));
  Vec3 points[2];
  int count = 0;
  const auto made_here = [&made](index_t w) { return static_cast<std::size_t>(w) < made.size() && made[w]; };
  if (options.split_in_thirds && options.resplit_halves && !made_here(a) && !made_here(b)) {
    const double scaled = e.entry.length * grid.density_at(mid, options.lookup);
    // n pieces of an edge at r / rho are |n / r - 1| off the target:
    // three are nearest for r in [2.5, 3.5).
    if (scaled >= 2.5 && scaled < 3.5) points[count++] = mesh.point(a) + (mesh.point(b) - mesh.point(a)) / 3.0;
  }
  points[count++] = mid;
  double old_min = std::numeric_limits<double>::infinity();
  bool old_known = false;
  for (int c = 0; c < count; ++c) {
    const Vec3& m = points[c];
    double new_min = std::numeric_limits<double>::infinity();
    for (const index_t t : e.ring) {
      new_min = std::min(new_min, stretch_with(mesh, t, kInvalidIndex, kInvalidIndex, a, m));
      new_min = std::min(new_min, stretch_with(mesh, t, kInvalidIndex, kInvalidIndex, b, m));
    }
    if (new_min < options.min_stretch && !old_known) {  // the tets as they are matter only then
      for (const index_t t : e.ring)
        old_min = std::min(old_min, stretch_with(mesh, t, kInvalidIndex, kInvalidIndex, kInvalidIndex, m));
      old_known = true;
    }
    e.accepted = !below_floor(new_min, options.split_relative_floor * old_min, options.min_stretch);
    e.point = m;
    if (e.accepted) break;
  }
  for (int k = 0; k < 2; ++k) {  // as scaled_length(mesh, grid, lookup, end, m) computes them
    const Vec3& p = mesh.point(k == 0 ? a : b);
    e.half_length[k] = (e.point - p).norm();
    e.half_scaled[k] = e.half_length[k] * grid.density_at(0.5 * (p + e.point), options.lookup);
  }
  if (e.accepted && options.merge_new_midpoints && !e.boundary) plan_merge(mesh, grid, options, made, e.point, marks, e);
}

}  // namespace

namespace {

/// Steps 1-3 (split_long_edges). With `shorts`, also the edges that
/// qualify for step 4 when the pass ends, which the collapse pass then need
/// not scan for: the scan of step 1 finds the short edges too, and a split
/// changes no edge but its own and those of its new vertex (a projection
/// moves only that vertex), so the short edges are the ones found by the
/// scan plus those of the new vertices still alive. Those are logged as the
/// splits make them (the new vertex with the edge's ends and ring), so no
/// ball is walked for them; a logged edge that a later split of the pass
/// took away was long, and no vertex moves after its split, so it is not
/// taken for a short one.
std::size_t split_pass(TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                       std::vector<char>& mask, DensityControlStats* stats, std::vector<HeapEdge>* shorts) {
  const double beta1 = options.split_threshold, beta2 = options.collapse_threshold;
  // Step 1: edges with L(e) >= beta1 / rho_GC(c_e) into a max-heap by length.
  std::vector<HeapEdge> longs;
  edges_passing(mesh, grid, options.lookup, mask, beta1, beta2, &longs, shorts, options.split_inner_edges);
  MaxEdgeQueue heap(std::move(longs));
  std::size_t splits = 0;
  std::vector<char> made;  // vertices this pass created
  std::vector<std::pair<index_t, index_t>> created;  // with `shorts`: the edges the splits made
  const auto made_here = [&made](index_t w) { return static_cast<std::size_t>(w) < made.size() && made[w]; };
  std::vector<index_t> ball;
  // Beyond the thesis: the longest edges are popped in batches, evaluated
  // in parallel (read only) and split in heap order; a candidate whose ring
  // an earlier split of its batch changed goes back into the heap. The
  // batches do not depend on the number of threads, so neither does the
  // result.
  constexpr std::size_t kBatch = 128;
  std::vector<SplitEval> batch(kBatch);
  std::vector<TetMesh::WalkMarks> marks(static_cast<std::size_t>(parallel_threads()));
  std::vector<std::uint32_t> changed;  // batch id per vertex an accepted split changed
  std::uint32_t batch_id = 0;
  // Steps 2-3: split the longest until the heap is empty.
  while (!heap.empty()) {
    std::size_t n = 0;
    while (n < kBatch && !heap.empty()) {
      const HeapEdge top = heap.pop();
      if (!mesh.vertex_alive(top.a) || !mesh.vertex_alive(top.b)) continue;
      // No vertex moves in this pass once an edge of it is queued (a
      // projection moves the new vertex before its halves are queued), so
      // the entry is still long (the field is fixed): no density lookup.
      // The length is compared as a guard: requeued while long.
      if ((mesh.point(top.b) - mesh.point(top.a)).norm() != top.length) {
        double length;
        if (scaled_length(mesh, grid, options.lookup, top.a, top.b, &length) >= beta1)
          heap.push({length, top.a, top.b, top.tag});
        continue;
      }
      batch[n++].entry = top;
    }
    const long count = static_cast<long>(n);
    parallel_for_worker(
        count,
        [&](long i, int worker) {
          evaluate_split(mesh, grid, options, made, marks[static_cast<std::size_t>(worker)],
                         batch[static_cast<std::size_t>(i)]);
        },
        32, 8);
    ++batch_id;
    if (changed.size() < static_cast<std::size_t>(mesh.vertex_slots()))
      changed.resize(static_cast<std::size_t>(mesh.vertex_slots()), 0);
    const auto untouched = [&](index_t w) {
      return static_cast<std::size_t>(w) >= changed.size() || changed[static_cast<std::size_t>(w)] != batch_id;
    };
    for (std::size_t i = 0; i < n; ++i) {
      SplitEval& e = batch[i];
      const HeapEdge top = e.entry;
      if (!untouched(top.a) || !untouched(top.b) || !std::all_of(e.opposite.begin(), e.opposite.end(), untouched)) {
        heap.push(top);  // evaluated on a ring that has changed since
        continue;
      }
      if (!e.is_edge) continue;
      // An edge with an unflagged end only when it is inner (split_inner_edges).
      if (e.boundary && !(masked(mask, top.a) && masked(mask, top.b))) continue;
      if (!e.accepted) {
        if (stats) ++stats->refused_splits;
        continue;
      }
      // The merge planned for it (plan_merge): an inner edge, whose split
      // needs no projection; checked on the mesh as it is (fresh).
      if (e.merge_into != kInvalidIndex &&
          mesh.flip_edge_to_fan(top.a, top.b, e.merge_into, e.ring, e.opposite, false) == OpStatus::Ok) {
        const index_t into = e.merge_into;
        ++splits;
        if (stats) ++stats->merged_midpoints;
        changed[static_cast<std::size_t>(top.a)] = batch_id;
        changed[static_cast<std::size_t>(top.b)] = batch_id;
        touch(options.touched, into);
        for (const index_t w : e.merge_neighbours) touch(options.touched, w);
        // `into` may be younger than this batch's marks.
        if (static_cast<std::size_t>(into) >= changed.size()) changed.resize(static_cast<std::size_t>(into) + 1, 0);
        changed[static_cast<std::size_t>(into)] = batch_id;
        if (shorts)
          for (const index_t w : e.merge_neighbours) created.push_back({std::min(into, w), std::max(into, w)});
        continue;
      }
      index_t v = kInvalidIndex;
      if (mesh.split_edge(top.a, top.b, &e.point, &v, e.ring, e.opposite, e.boundary) != OpStatus::Ok) {
        if (stats) ++stats->refused_splits;
        continue;
      }
      changed[static_cast<std::size_t>(top.a)] = batch_id;
      changed[static_cast<std::size_t>(top.b)] = batch_id;
      // The midpoint of a planar boundary edge is on its plane; curved
      // regions are projected by the caller's callback. A new vertex that
      // cannot be put on its surface is taken back (the half-edge collapse
      // onto an end restores the tets): boundary vertices stay on the
      // fitted surfaces.
      if (e.boundary && options.project && mesh.on_boundary(v)) {
        const Projection p = try_project(mesh, v, options, ball);
        if (p == Projection::Refused) {
          mesh.half_edge_collapse(Keep{top.a}, Remove{v});
          if (stats) ++stats->refused_splits;
          continue;
        }
        if (p == Projection::Moved && stats) ++stats->projections;
      }
      ++splits;
      for (const index_t w : {v, top.a, top.b}) touch(options.touched, w);
      for (const index_t w : e.opposite) touch(options.touched, w);
      if (shorts) {
        for (const index_t w : {top.a, top.b}) created.push_back({std::min(v, w), std::max(v, w)});
        for (const index_t w : e.opposite) created.push_back({std::min(v, w), std::max(v, w)});
      }
      // Beyond the thesis: the halves of an edge the pass started with go
      // back into the heap when still long (an edge stretched x3 needs two
      // halvings; left to the next loop, the collapses in between undo part
      // of the first). Not their halves: without smoothing in between,
      // repeated halving of a fan packs midpoints too closely (on a cube
      // stretched x12 the density error ends higher).
      const bool original_edge = !made_here(top.a) && !made_here(top.b);
      if (static_cast<std::size_t>(v) >= made.size()) made.resize(static_cast<std::size_t>(v) + 1, 0);
      made[v] = 1;
      if (options.resplit_halves && original_edge) {
        const bool at_point = mesh.point(v) == e.point;  // not moved by a projection
        for (int k = 0; k < 2; ++k) {
          const index_t end = k == 0 ? top.a : top.b;
          double half = e.half_length[k], scaled = e.half_scaled[k];
          if (!at_point) scaled = scaled_length(mesh, grid, options.lookup, end, v, &half);
          if (scaled >= beta1) heap.push({half, std::min(end, v), std::max(end, v)});
        }
      }
      if (!mask.empty()) {
        if (static_cast<std::size_t>(v) >= mask.size()) mask.resize(static_cast<std::size_t>(v) + 1, 0);
        mask[v] = 1;
      }
    }
  }
  if (shorts) {
    // The short edges among those the splits made.
    const long count = static_cast<long>(created.size());
    *shorts = parallel_reduce(
        count, std::move(*shorts),
        [&](long begin, long end, int) {
          std::vector<HeapEdge> out;
          for (long i = begin; i < end; ++i) {
            const auto [a, b] = created[static_cast<std::size_t>(i)];
            if (!masked(mask, a) || !masked(mask, b)) continue;
            double length;
            const double scaled = scaled_length(mesh, grid, options.lookup, a, b, &length);
            if (scaled > 0 && scaled <= beta2) out.push_back({length, a, b});
          }
          return out;
        },
        append<HeapEdge>);
    sort_unique_by_ends(*shorts);
  }
  return splits;
}

}  // namespace

std::size_t split_long_edges(TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                             std::vector<char>& mask, DensityControlStats* stats) {
  return split_pass(mesh, grid, options, mask, stats, nullptr);
}

namespace {

/// A collapse candidate popped from the heap and what its evaluation found.
struct CollapseEval {
  enum Result { NotAnEdge, Refused, Accepted, NeedsProjection };
  HeapEdge entry{};
  Result result = NotAnEdge;
  CollapsePlan plan;
  Vec3 position = Vec3::Zero();
  bool projected = false;
  // Both balls, and the vertices of their tets except the two ends (the
  // surviving vertex's neighbours); only a's ball when the rules refuse.
  std::vector<index_t> ball_a, ball_keep, ball_remove, neighbours;
  // Per candidate position (3 x neighbours): the length and scaled length
  // of the surviving vertex's edge to each neighbour, as the long-edge test
  // found them; those of the chosen position are the edges the commit
  // queues when short, with no density lookup in the serial part.
  std::vector<double> lengths, scaled;
  int chosen = 0;  // the candidate position taken
};

/// Step 6 for one candidate without changing the mesh: the rules of
/// Fig. 2.37, then the best position (the rules' one; with equal classes
/// also either end) that creates no splittable edge, keeps the stretch floor
/// and (on the boundary) the chord error, and the collapse's own checks
/// there (TetMesh::check_collapse). Read only, with the caller's walk
/// marks and stamps, so candidates can be evaluated in parallel; a boundary
/// vertex to be projected (the callback may walk the mesh's own marks) is
/// left as NeedsProjection unless `may_project`.
void evaluate_collapse(const TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                       bool may_project, TetMesh::WalkMarks& marks, TetMesh::VertexStamps& seen,
                       TetMesh::VertexStamps& link_stamps, CollapseEval& e) {
  const index_t a = e.entry.a, b = e.entry.b;
  e.result = CollapseEval::NotAnEdge;
  e.neighbours.clear();
  // a's ball finds a tet on the edge and serves as that end's ball below.
  mesh.vertex_ball(a, e.ball_a, marks);
  index_t hint = kInvalidIndex;
  for (const index_t t : e.ball_a)
    if (mesh.local_index(t, b) >= 0) {
      hint = t;
      break;
    }
  if (hint < 0) return;
  e.result = CollapseEval::Refused;
  CollapsePlan& plan = e.plan;
  plan = mesh.plan_collapse_by_rules(a, b, hint);
  if (plan.status != OpStatus::Ok) return;
  if (plan.keep == a) {
    e.ball_keep.swap(e.ball_a);
    mesh.vertex_ball(plan.remove, e.ball_remove, marks);
  } else {
    e.ball_remove.swap(e.ball_a);
    mesh.vertex_ball(plan.keep, e.ball_keep, marks);
  }
  ball_vertices(mesh, e.ball_keep, e.ball_remove, plan.keep, plan.remove, seen, e.neighbours);
  e.projected = false;
  if (options.project && mesh.on_boundary(plan.keep) && plan.position != mesh.point(plan.keep)) {
    if (!may_project) {  // after the balls: the caller checks the same neighbourhood
      e.result = CollapseEval::NeedsProjection;
      return;
    }
    const Vec3 q = options.project(plan.keep, plan.position);
    if (q.allFinite()) {
      e.projected = q != plan.position;
      plan.position = q;
    }
  }
  // Candidate positions of the surviving vertex: the rules' position
  // (Fig. 2.37); when both ends have the same class (on one region or
  // curve), also the two ends themselves (half-edge collapses, Fig. 2.39),
  // which stay on that region or curve.
  const Vec3 candidates[3] = {plan.position, mesh.point(plan.keep), mesh.point(plan.remove)};
  const VertexClass ck = mesh.vertex_class(plan.keep);
  const int n_candidates = ck == mesh.vertex_class(plan.remove) && ck != VertexClass::Corner ? 3 : 1;
  const bool boundary_collapse =
      options.accept_boundary_collapse && (mesh.on_boundary(plan.keep) || mesh.on_boundary(plan.remove));
  e.lengths.resize(3 * e.neighbours.size());
  e.scaled.resize(3 * e.neighbours.size());
  double old_min = std::numeric_limits<double>::quiet_NaN();
  int best = -1;
  double best_min = -std::numeric_limits<double>::infinity();
  for (int c = 0; c < n_candidates; ++c) {
    const Vec3& x = candidates[c];
    if (c > 0 && x == candidates[0]) continue;
    // No edge of the surviving vertex may become long enough to be split
    // (else a split and a collapse can undo each other forever; the
    // thesis' convergence condition on beta1, beta2 assumes this).
    bool creates_long_edge = false;
    const std::size_t row = static_cast<std::size_t>(c) * e.neighbours.size();
    for (std::size_t i = 0; i < e.neighbours.size(); ++i) {
      const Vec3& q = mesh.point(e.neighbours[i]);
      const double length = (q - x).norm();
      const double s = length * grid.density_at(0.5 * (q + x), options.lookup);
      e.lengths[row + i] = length;
      e.scaled[row + i] = s;
      creates_long_edge = s >= options.split_threshold;
      if (creates_long_edge) break;
    }
    if (creates_long_edge) continue;
    // Stretch floor over the tets that survive, with remove renamed keep
    // and keep moved to x; a candidate no better than the best so far is
    // dropped as soon as one tet shows it.
    double new_min = std::numeric_limits<double>::infinity();
    for (const std::vector<index_t>* ball : {&e.ball_keep, &e.ball_remove}) {
      for (const index_t t : *ball) {
        if (mesh.local_index(t, plan.keep) >= 0 && mesh.local_index(t, plan.remove) >= 0) continue;  // vanishes
        new_min = std::min(new_min, stretch_with(mesh, t, plan.remove, plan.keep, plan.keep, x));
        if (new_min <= best_min) break;
      }
      if (new_min <= best_min) break;
    }
    if (new_min <= best_min) continue;
    // The worst tet as it is matters only below the floor.
    if (new_min < options.min_stretch && std::isnan(old_min)) {
      old_min = std::numeric_limits<double>::infinity();
      for (const std::vector<index_t>* ball : {&e.ball_keep, &e.ball_remove})
        for (const index_t t : *ball)
          old_min = std::min(old_min, stretch_with(mesh, t, kInvalidIndex, kInvalidIndex, kInvalidIndex, x));
    }
    if (below_floor(new_min, old_min, options.min_stretch)) continue;
    if (boundary_collapse &&
        !options.accept_boundary_collapse(plan.keep, plan.remove, x, e.ball_keep, e.ball_remove))
      continue;
    best = c;
    best_min = new_min;
  }
  if (best < 0) return;
  e.position = candidates[best];
  e.chosen = best;
  e.projected = e.projected && best == 0;
  if (mesh.check_collapse(Keep{plan.keep}, Remove{plan.remove}, e.position, e.ball_keep, e.ball_remove,
                          link_stamps) != OpStatus::Ok)
    return;
  e.result = CollapseEval::Accepted;
}

}  // namespace

namespace {

/// Steps 4-7 (collapse_short_edges) from the edges of step 4, sorted by
/// ends (edges_passing).
std::size_t collapse_pass(TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                          const std::vector<char>& mask, DensityControlStats* stats, std::vector<HeapEdge> shorts) {
  const double beta2 = options.collapse_threshold;
  const auto qualifies = [&](index_t a, index_t b, double* length) {
    const double s = scaled_length(mesh, grid, options.lookup, a, b, length);
    return s > 0 && s <= beta2;
  };
  // Step 4: edges with L(e) <= beta2 / rho_GC(c_e) into a min-heap.
  // The pass's clock: an entry made at time t (HeapEdge::tag) is as its
  // ends are when neither has moved at t or later (moved_at; the clock
  // ticks at every collapse, whose surviving vertex is the only one that
  // moves).
  index_t clock = 1;
  std::vector<index_t> moved_at(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  for (HeapEdge& h : shorts) h.tag = clock;
  MinEdgeQueue heap(std::move(shorts));
  std::size_t collapses = 0;
  // Beyond the thesis: the shortest edges are popped in batches and
  // evaluated in parallel (read only), then collapsed in heap order; a
  // candidate whose neighbourhood an earlier collapse of its batch changed
  // goes back into the heap. The batches do not depend on the number of
  // threads, so neither does the result.
  constexpr std::size_t kBatch = 128;
  std::vector<CollapseEval> batch(kBatch);
  const int threads = parallel_threads();
  std::vector<TetMesh::WalkMarks> marks(static_cast<std::size_t>(threads));
  std::vector<TetMesh::VertexStamps> seen(static_cast<std::size_t>(threads));
  std::vector<TetMesh::VertexStamps> link_stamps(static_cast<std::size_t>(threads));
  std::vector<std::uint32_t> changed(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  std::uint32_t batch_id = 0;
  HeapEdge previous{-1, kInvalidIndex, kInvalidIndex};
  while (!heap.empty()) {
    // Step 5: pop the shortest (stale entries: the edge is gone or changed;
    // a copy of the entry just handled would find the mesh as it left it).
    std::size_t n = 0;
    while (n < kBatch && !heap.empty()) {
      const HeapEdge top = heap.pop();
      if (top.length == previous.length && top.a == previous.a && top.b == previous.b) continue;
      previous = top;
      if (!mesh.vertex_alive(top.a) || !mesh.vertex_alive(top.b)) continue;
      // Ends unmoved since the entry was made: still short (the field is
      // fixed), no density lookup. Else checked again: dropped when no
      // longer short, requeued when its length changed.
      if (moved_at[static_cast<std::size_t>(top.a)] >= top.tag ||
          moved_at[static_cast<std::size_t>(top.b)] >= top.tag) {
        double length;
        if (!qualifies(top.a, top.b, &length)) continue;
        if (length != top.length) {
          heap.push({length, top.a, top.b, clock + 1});
          continue;
        }
      } else if (options.check_queue && stats) {
        double length;
        ++stats->queue_checked;
        if (!qualifies(top.a, top.b, &length) || length != top.length) ++stats->queue_disagreements;
      }
      batch[n++].entry = top;
    }
    const long count = static_cast<long>(n);
    parallel_for_worker(
        count,
        [&](long i, int id) {
          evaluate_collapse(mesh, grid, options, options.project_in_parallel, marks[static_cast<std::size_t>(id)],
                            seen[static_cast<std::size_t>(id)], link_stamps[static_cast<std::size_t>(id)],
                            batch[static_cast<std::size_t>(i)]);
        },
        32, 8);
    // Step 6 in heap order.
    ++batch_id;
    const auto untouched = [&](index_t v) { return changed[static_cast<std::size_t>(v)] != batch_id; };
    for (std::size_t i = 0; i < n; ++i) {
      CollapseEval& e = batch[i];
      const bool fresh =
          untouched(e.entry.a) && untouched(e.entry.b) &&
          std::all_of(e.neighbours.begin(), e.neighbours.end(), untouched) &&
          (e.result != CollapseEval::Refused || !e.neighbours.empty() ||
           std::all_of(e.ball_a.begin(), e.ball_a.end(), [&](index_t t) {
             return mesh.tet_alive(t) && std::all_of(mesh.tet(t).begin(), mesh.tet(t).end(), untouched);
           }));
      if (!fresh) {  // evaluated on a neighbourhood that has changed since
        heap.push(e.entry);
        continue;
      }
      if (e.result == CollapseEval::NotAnEdge) continue;
      if (e.result == CollapseEval::NeedsProjection)
        evaluate_collapse(mesh, grid, options, true, marks[0], seen[0], link_stamps[0], e);
      // A fresh candidate was checked on the mesh as it is.
      if (e.result != CollapseEval::Accepted ||
          mesh.collapse_checked_edge(Keep{e.plan.keep}, Remove{e.plan.remove}, e.position, e.ball_keep,
                                     e.ball_remove) != OpStatus::Ok) {
        if (stats) ++stats->refused_collapses;
        continue;
      }
      ++collapses;
      touch(options.touched, e.plan.keep);
      touch(options.touched, e.plan.remove);
      for (const index_t w : e.neighbours) touch(options.touched, w);
      moved_at[static_cast<std::size_t>(e.plan.keep)] = ++clock;
      if (e.projected && stats) ++stats->projections;
      changed[static_cast<std::size_t>(e.plan.keep)] = batch_id;
      changed[static_cast<std::size_t>(e.plan.remove)] = batch_id;
      // Edges around the surviving vertex (its neighbours are `neighbours`)
      // that now qualify go into the heap (duplicates are harmless: stale
      // entries are skipped when popped).
      // Their lengths are the evaluation's: keep is where it was put and
      // the neighbours have not moved (the candidate was fresh).
      const index_t keep = e.plan.keep;
      const std::size_t row = static_cast<std::size_t>(e.chosen) * e.neighbours.size();
      for (std::size_t i = 0; i < e.neighbours.size(); ++i) {
        const index_t w = e.neighbours[i];
        if (!masked(mask, w) || !masked(mask, keep)) continue;
        const double scaled = e.scaled[row + i];
        if (scaled > 0 && scaled <= beta2)
          heap.push({e.lengths[row + i], std::min(keep, w), std::max(keep, w), clock + 1});
      }
    }
  }
  return collapses;
}

}  // namespace

std::size_t collapse_short_edges(TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                                 const std::vector<char>& mask, DensityControlStats* stats) {
  std::vector<HeapEdge> shorts;
  edges_passing(mesh, grid, options.lookup, mask, std::numeric_limits<double>::infinity(), options.collapse_threshold,
                nullptr, &shorts);
  return collapse_pass(mesh, grid, options, mask, stats, std::move(shorts));
}

DensityControlStats control_mesh_density(TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options) {
  DensityControlStats stats;
  if (options.measure_error) stats.error_before = mean_density_error(mesh, grid, options.lookup);
  if (grid.empty()) {
    stats.error_after = stats.error_before;
    stats.converged = true;
    return stats;
  }
  std::vector<char> mask = options.vertex_mask;
  for (int round = 0; round < options.max_iterations; ++round) {
    ++stats.iterations;
    std::vector<HeapEdge> shorts;
    const std::size_t s = split_pass(mesh, grid, options, mask, &stats, &shorts);
    const std::size_t c = collapse_pass(mesh, grid, options, mask, &stats, std::move(shorts));
    stats.splits += s;
    stats.collapses += c;
    if (s == 0 && c == 0) {
      stats.converged = true;
      break;
    }
  }
  if (options.measure_error) stats.error_after = mean_density_error(mesh, grid, options.lookup);
  return stats;
}

}  // namespace femorph
