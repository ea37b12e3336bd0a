// Shape approximation accuracy control, thesis 2.6.4.
#include "improve/control_shape_accuracy.h"

#include "improve/optimize_worst_vertices.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace femorph {

namespace {

bool curved(const SurfacePrimitive* s) { return s && s->type != SurfaceType::Plane; }

/// The three edges of boundary face f of tet t (local vertex f is opposite).
template <class Fn>
void for_face_edges(const TetMesh& mesh, index_t t, int f, Fn&& fn) {
  const Tet& T = mesh.tet(t);
  index_t v[3];
  for (int i = 0, k = 0; i < 4; ++i)
    if (i != f) v[k++] = T[i];
  for (int e = 0; e < 3; ++e) fn(v[e], v[(e + 1) % 3]);
}

double min_stretch_of(const TetMesh& mesh, const std::vector<index_t>& tets) {
  double q = std::numeric_limits<double>::infinity();
  for (const index_t t : tets) {
    const Tet& T = mesh.tet(t);
    q = std::min(q, tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3])));
  }
  return q;
}

bool masked(const std::vector<std::uint8_t>& mask, index_t v) {
  return mask.empty() || static_cast<std::size_t>(v) >= mask.size() || mask[v];
}

/// The chords of tet t's boundary faces on curved regions that hold its
/// local vertex lv, with that vertex at p: each within its region's
/// acceptable error or no longer than it was.
bool face_chords_within_error(const TetMesh& mesh, const BoundaryGeometry& geometry,
                              const std::vector<double>& acceptable, index_t t, int lv, const Vec3& p) {
  const Tet& T = mesh.tet(t);
  const Vec3& x = mesh.point(T[lv]);
  for (int f = 0; f < 4; ++f) {
    if (f == lv || !mesh.is_boundary_face(t, f)) continue;
    const index_t r = mesh.face_region(t, f);
    const SurfacePrimitive* s = geometry.region(r);
    if (!curved(s) || r < 0 || static_cast<std::size_t>(r) >= acceptable.size() || !(acceptable[r] > 0)) continue;
    for (int k = 0; k < 4; ++k) {
      if (k == f || k == lv) continue;
      const Vec3& w = mesh.point(T[k]);
      const double after = distance(*s, 0.5 * (p + w));
      if (after > acceptable[r] && after > distance(*s, 0.5 * (x + w))) return false;
    }
  }
  return true;
}

struct Entry {
  double error;
  index_t a, b, region;
  bool operator<(const Entry& o) const {  // max-heap on error, ties by ids
    if (error != o.error) return error < o.error;
    if (a != o.a) return a > o.a;
    return b > o.b;
  }
};

}  // namespace

namespace {

/// Raises error[r] to the chord error of the edges of one boundary face
/// (corners a, b, c) of region r, when r is curved.
void add_face_chord_error(const BoundaryGeometry& geometry, index_t r, const Vec3& a, const Vec3& b, const Vec3& c,
                          std::vector<double>& error) {
  const SurfacePrimitive* s = geometry.region(r);
  if (!curved(s)) return;
  const Vec3* corner[3] = {&a, &b, &c};
  for (int e = 0; e < 3; ++e) {
    const double d = distance(*s, 0.5 * (*corner[e] + *corner[(e + 1) % 3]));
    if (!(d <= error[r])) error[r] = std::isnan(error[r]) ? d : std::max(error[r], d);
  }
}

}  // namespace

std::vector<double> region_geometric_error(const TetMesh& mesh, const BoundaryGeometry& geometry) {
  std::vector<double> error(geometry.regions.size(), std::numeric_limits<double>::quiet_NaN());
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const Tet& T = mesh.tet(t);
    for (int f = 0; f < 4; ++f)
      if (mesh.is_boundary_face(t, f))
        add_face_chord_error(geometry, mesh.face_region(t, f), mesh.point(T[kTetFace[f][0]]),
                             mesh.point(T[kTetFace[f][1]]), mesh.point(T[kTetFace[f][2]]), error);
  }
  return error;
}

std::vector<double> region_geometric_error(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                                           const std::vector<Tet>& face_regions, const BoundaryGeometry& geometry) {
  std::vector<double> error(geometry.regions.size(), std::numeric_limits<double>::quiet_NaN());
  const std::size_t n = std::min(tets.size(), face_regions.size());
  for (std::size_t t = 0; t < n; ++t) {
    const Tet& T = tets[t];
    for (int f = 0; f < 4; ++f)
      if (face_regions[t][f] >= 0)
        add_face_chord_error(geometry, face_regions[t][f], points[T[kTetFace[f][0]]], points[T[kTetFace[f][1]]],
                             points[T[kTetFace[f][2]]], error);
  }
  return error;
}

bool chords_within_error(const TetMesh& mesh, const BoundaryGeometry& geometry, const std::vector<double>& acceptable,
                         index_t v, const Vec3& p) {
  thread_local std::vector<index_t> ball;
  mesh.vertex_ball(v, ball);
  return chords_within_error(mesh, geometry, acceptable, v, p, ball);
}

bool chords_within_error(const TetMesh& mesh, const BoundaryGeometry& geometry, const std::vector<double>& acceptable,
                         index_t v, const Vec3& p, const std::vector<index_t>& ball) {
  for (const index_t t : ball)
    if (!face_chords_within_error(mesh, geometry, acceptable, t, mesh.local_index(t, v), p)) return false;
  return true;
}

bool collapse_chords_within_error(const TetMesh& mesh, const BoundaryGeometry& geometry,
                                  const std::vector<double>& acceptable, index_t keep, index_t remove, const Vec3& x,
                                  const std::vector<index_t>& ball_keep, const std::vector<index_t>& ball_remove) {
  for (const std::vector<index_t>* ball : {&ball_keep, &ball_remove})
    for (const index_t t : *ball) {
      const int lk = mesh.local_index(t, keep), lr = mesh.local_index(t, remove);
      if (lk >= 0 && lr >= 0) continue;  // vanishes
      if (!face_chords_within_error(mesh, geometry, acceptable, t, lk >= 0 ? lk : lr, x)) return false;
    }
  return true;
}

AccuracyControlStats control_shape_accuracy(TetMesh& mesh, const BoundaryGeometry& geometry,
                                            const std::vector<double>& acceptable,
                                            const AccuracyControlOptions& options) {
  AccuracyControlStats stats;
  const auto limit = [&](index_t r) {
    return r >= 0 && static_cast<std::size_t>(r) < acceptable.size() && acceptable[r] > 0
               ? acceptable[r]
               : std::numeric_limits<double>::quiet_NaN();
  };
  // Edges of boundary face f of t over their region's limit go on the heap.
  std::priority_queue<Entry> heap;
  const auto push_face = [&](index_t t, int f) {
    const index_t r = mesh.face_region(t, f);
    const SurfacePrimitive* s = geometry.region(r);
    const double lim = limit(r);
    if (!curved(s) || !(lim > 0)) return;
    for_face_edges(mesh, t, f, [&](index_t a, index_t b) {
      if (!masked(options.vertex_mask, a) || !masked(options.vertex_mask, b)) return;
      const double d = distance(*s, 0.5 * (mesh.point(a) + mesh.point(b)));
      if (d > lim) heap.push({d, std::min(a, b), std::max(a, b), r});  // once per face: stale copies are skipped
    });
  };
  if (acceptable.empty()) return stats;
  for (index_t t = 0; t < mesh.tet_slots(); ++t)
    if (mesh.tet_alive(t))
      for (int f = 0; f < 4; ++f)
        if (mesh.is_boundary_face(t, f)) push_face(t, f);
  stats.edges_over = heap.size();  // each edge once per region it bounds
  const std::size_t max_splits = options.max_splits ? options.max_splits : 4 * heap.size() + 100;

  std::vector<index_t> ring, ball, around;
  std::vector<std::pair<index_t, Vec3>> moved;  // inner vertices moved for a split, to undo
  while (!heap.empty() && stats.splits < max_splits) {
    const Entry e = heap.top();
    heap.pop();
    if (!mesh.vertex_alive(e.a) || !mesh.vertex_alive(e.b)) continue;
    bool boundary = false;
    if (!mesh.edge_ring(e.a, e.b, ring, &boundary) || !boundary) continue;
    const double old_min = min_stretch_of(mesh, ring);
    index_t v = kInvalidIndex;
    if (mesh.split_edge(e.a, e.b, nullptr, &v, ring.front()) != OpStatus::Ok) {
      ++stats.refused;
      continue;
    }
    // Fig. 2.41 (b): the new vertex goes onto the fitted surface (or curve).
    const VertexConstraint c = vertex_constraint(mesh, geometry, v);
    Vec3 q;
    bool ok = c.kind == VertexConstraint::Surface || c.kind == VertexConstraint::Curve;
    ok = ok && project_to_constraint(c, mesh.point(v), &q) && mesh.move_vertex(v, q) == OpStatus::Ok;
    moved.clear();
    if (ok) {
      mesh.vertex_ball(v, ball);
      double new_min = min_stretch_of(mesh, ball);
      if (new_min < options.min_stretch && new_min < old_min) {
        // The projected vertex flattened a tet: place the inner vertices
        // around it for the best ball quality before giving up.
        around.clear();
        for (const index_t t : ball)
          for (const index_t w : mesh.tet(t))
            if (mesh.vertex_class(w) == VertexClass::Inner && masked(options.vertex_mask, w)) around.push_back(w);
        std::sort(around.begin(), around.end());
        around.erase(std::unique(around.begin(), around.end()), around.end());
        for (const index_t w : around) {
          const Vec3 before = mesh.point(w);
          compass_search_vertex(mesh, w);
          if (mesh.point(w) != before) moved.emplace_back(w, before);
        }
        mesh.vertex_ball(v, ball);
        new_min = min_stretch_of(mesh, ball);
      }
      ok = !(new_min < options.min_stretch && new_min < old_min);
    }
    if (!ok) {
      for (auto it = moved.rbegin(); it != moved.rend(); ++it) mesh.set_point(it->first, it->second);
      mesh.half_edge_collapse(Keep{e.a}, Remove{v});  // restores the tets of the edge
      ++stats.refused;
      continue;
    }
    ++stats.splits;
    // The new boundary edges at v (halves and the edges to the opposite
    // vertices) are checked again.
    mesh.vertex_ball(v, ball);
    if (options.touched) {
      std::vector<char>& touched = *options.touched;
      if (touched.size() < static_cast<std::size_t>(mesh.vertex_slots()))
        touched.resize(static_cast<std::size_t>(mesh.vertex_slots()), 0);
      for (const index_t t : ball)
        for (const index_t w : mesh.tet(t)) touched[static_cast<std::size_t>(w)] = 1;
      for (const auto& m : moved) touched[static_cast<std::size_t>(m.first)] = 1;
    }
    for (const index_t t : ball)
      for (int f = 0; f < 4; ++f)
        if (mesh.is_boundary_face(t, f) && mesh.tet(t)[f] != v) push_face(t, f);
  }
  return stats;
}

}  // namespace femorph
