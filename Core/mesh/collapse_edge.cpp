// Edge collapse, thesis 2.6.1.3 Fig. 2.36 (a), and the half-edge collapse of
// Fig. 2.39 (the inverted-element removal of 2.6.2) as its special case.
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"
#include "mesh/vertex_stencil.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace femorph {
namespace {

using Pair = std::pair<index_t, index_t>;

inline Pair ordered(index_t x, index_t y) { return x < y ? Pair(x, y) : Pair(y, x); }

template <class T>
inline bool contains(const std::vector<T>& v, const T& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

bool TetMesh::link_condition(index_t a, index_t b, const std::vector<index_t>& ball_a,
                             const std::vector<index_t>& ball_b, const std::vector<index_t>& ring, std::uint32_t* mark,
                             std::uint32_t in_a, std::uint32_t in_ring) const {
  // Lk(a) n Lk(b) = Lk(ab) (Dey et al.; thesis 2.6.1.3), with a vertex at
  // infinity joined to every boundary face so that boundary and interior are
  // treated alike. Lk(ab) is the ring of the edge: its opposite vertices R,
  // the consecutive pairs, and infinity with the two ends when the ring is
  // open. Checked with vertex marks over the two balls.
  thread_local std::vector<index_t> ring_vertices, ends, inf_a, inf_b;
  thread_local std::vector<Pair> ring_pairs, pairs_a, pairs_b, bpairs_a, bpairs_b;
  ring_vertices.clear();
  ends.clear();
  ring_pairs.clear();
  for (index_t t : ring) {
    const TetRecord& R = rec_[t];
    int lx[2], n = 0;
    for (int i = 0; i < 4; ++i)
      if (R.v[i] != a && R.v[i] != b) lx[n++] = i;
    ring_pairs.push_back(ordered(R.v[lx[0]], R.v[lx[1]]));
    for (int k = 0; k < 2; ++k) {
      const index_t x = R.v[lx[k]];
      if (!contains(ring_vertices, x)) ring_vertices.push_back(x);
      // Face (a, b, x) is opposite the other one: on the boundary, x is an
      // end of the open ring.
      if (R.n[lx[1 - k]] < 0) ends.push_back(x);
    }
  }
  const bool open_ring = !ends.empty();

  // Marks: every vertex of Lk(a) gets `in_a`, then the ring vertices (a
  // subset) get `in_ring`.
  bool a_on_boundary = false, b_on_boundary = false;
  for (index_t t : ball_a) {
    const TetRecord& R = rec_[t];
    for (int f = 0; f < 4; ++f) {
      mark[R.v[f]] = in_a;
      if (R.n[f] < 0 && R.v[f] != a) a_on_boundary = true;
    }
  }
  for (index_t x : ring_vertices) mark[x] = in_ring;

  // Vertices: every common neighbour of a and b is in R; infinity is common
  // (both on the boundary) only if the edge is on the boundary.
  for (index_t t : ball_b) {
    const TetRecord& R = rec_[t];
    for (int f = 0; f < 4; ++f) {
      const index_t w = R.v[f];
      if (R.n[f] < 0 && w != b) b_on_boundary = true;
      if (w != a && w != b && mark[w] == in_a) return false;
    }
  }
  if (a_on_boundary && b_on_boundary && !open_ring) return false;

  // Edges and triangles with all ends in R: faces (v, x, y) of the balls with
  // x, y in R, and boundary faces likewise (edges to infinity).
  auto collect = [&](index_t v, const std::vector<index_t>& ball, std::vector<Pair>& pairs,
                     std::vector<Pair>& boundary_pairs, std::vector<index_t>& inf_edges, int* ring_tets) {
    pairs.clear();
    boundary_pairs.clear();
    inf_edges.clear();
    *ring_tets = 0;
    for (index_t t : ball) {
      const TetRecord& R = rec_[t];
      int in_r = 0;
      for (index_t w : R.v) in_r += (w != v && mark[w] == in_ring);
      if (in_r == 3) ++*ring_tets;  // tet (v, x, y, z) with x, y, z in R
      for (int f = 0; f < 4; ++f) {
        if (R.v[f] == v) continue;
        index_t xy[2];
        int n = 0;
        for (int k = 0; k < 3; ++k) {
          const index_t w = R.v[kTetFace[f][k]];
          if (w != v) xy[n++] = w;
        }
        const bool x_in = mark[xy[0]] == in_ring, y_in = mark[xy[1]] == in_ring;
        if (x_in && y_in) {
          const Pair p = ordered(xy[0], xy[1]);
          if (!contains(pairs, p)) pairs.push_back(p);
          if (R.n[f] < 0) boundary_pairs.push_back(p);
        }
        if (R.n[f] < 0) {
          if (x_in) inf_edges.push_back(xy[0]);
          if (y_in) inf_edges.push_back(xy[1]);
        }
      }
    }
  };
  int ring_tets_a = 0, ring_tets_b = 0;
  collect(a, ball_a, pairs_a, bpairs_a, inf_a, &ring_tets_a);
  collect(b, ball_b, pairs_b, bpairs_b, inf_b, &ring_tets_b);
  for (const Pair& p : pairs_a)
    if (contains(pairs_b, p) && !contains(ring_pairs, p)) return false;
  for (index_t x : inf_a)
    if (contains(inf_b, x) && !contains(ends, x)) return false;
  // Triangles: Lk(ab) has none, so no triangle may be common: neither a tet
  // (a, x, y, z) and (b, x, y, z), nor boundary faces (a, x, y) and (b, x, y).
  if (ring_vertices.size() == 3 && ring_tets_a > 0 && ring_tets_b > 0) return false;
  for (const Pair& p : bpairs_a)
    if (contains(bpairs_b, p)) return false;
  return true;
}

OpStatus TetMesh::collapse_edge(Keep keep, Remove remove, const Vec3* position) {
  return collapse_edge_with(keep, remove, position, nullptr, nullptr);
}

OpStatus TetMesh::collapse_edge(Keep keep, Remove remove, const Vec3* position,
                                const std::vector<index_t>& ball_keep, const std::vector<index_t>& ball_remove) {
  return collapse_edge_with(keep, remove, position, &ball_keep, &ball_remove);
}

bool TetMesh::collapse_cavity(Keep keep, const std::vector<index_t>& ball_remove, std::vector<index_t>& ring) {
  // Tets of ball(remove) on the edge vanish; the others stay, with remove
  // renamed keep.
  ring.clear();
  for (index_t t : ball_remove)
    if (local_index(t, keep.id) >= 0) ring.push_back(t);
  return !ring.empty();
}

OpStatus TetMesh::collapse_edge_with(Keep keep_vertex, Remove remove_vertex, const Vec3* position,
                                     const std::vector<index_t>* given_keep,
                                     const std::vector<index_t>* given_remove) {
  const index_t keep = keep_vertex.id, remove = remove_vertex.id;
  if (!vertex_alive(keep) || !vertex_alive(remove) || keep == remove) return OpStatus::InvalidArgument;
  const Vec3 p = position ? *position : points_[keep];
  if (!given_remove) vertex_ball(remove, scratch_ball2_);
  if (!given_keep) vertex_ball(keep, scratch_ball_);
  const std::vector<index_t>& ball_remove = given_remove ? *given_remove : scratch_ball2_;
  const std::vector<index_t>& ball_keep = given_keep ? *given_keep : scratch_ball_;
  const OpStatus checked = check_collapse(keep_vertex, remove_vertex, p, ball_keep, ball_remove, link_stamps_);
  if (checked != OpStatus::Ok) return checked;
  return collapse_checked_edge(keep_vertex, remove_vertex, p, ball_keep, ball_remove);
}

OpStatus TetMesh::check_collapse(Keep keep_vertex, Remove remove_vertex, const Vec3& p,
                                 const std::vector<index_t>& ball_keep, const std::vector<index_t>& ball_remove,
                                 VertexStamps& stamps) const {
  const index_t keep = keep_vertex.id, remove = remove_vertex.id;
  if (!vertex_alive(keep) || !vertex_alive(remove) || keep == remove || !p.allFinite())
    return OpStatus::InvalidArgument;
  // Not an edge; a tet of remove's ball that stays (remove renamed keep)
  // or of keep's ball (keep moved to p) would not be positive; the link
  // condition last, as it costs more than the orientation tests.
  auto positive_after = [&](const Tet& T) {
    const Vec3* q[4];
    for (int i = 0; i < 4; ++i) q[i] = (T[i] == keep || T[i] == remove) ? &p : &points_[T[i]];
    return orient3d_sign(*q[0], *q[1], *q[2], *q[3]) > 0;
  };
  thread_local std::vector<index_t> ring;
  ring.clear();
  for (index_t t : ball_remove)
    if (local_index(t, keep) >= 0) ring.push_back(t);
  if (ring.empty()) return OpStatus::InvalidArgument;
  for (index_t t : ball_remove)
    if (local_index(t, keep) < 0 && !positive_after(rec_[t].v) && !(keep_inverted_ && orientation(t) < 0))
      return OpStatus::Inverted;
  if (p != points_[keep])
    for (index_t t : ball_keep)
      if (local_index(t, remove) < 0 && !positive_after(rec_[t].v)) return OpStatus::Inverted;
  const std::uint32_t in_a = stamps.next(points_.size());
  const std::uint32_t in_ring = stamps.next(points_.size());
  if (!link_condition(keep, remove, ball_keep, ball_remove, ring, stamps.stamp.data(), in_a, in_ring))
    return OpStatus::LinkCondition;
  return OpStatus::Ok;
}

OpStatus TetMesh::collapse_checked_edge(Keep keep, Remove remove, const Vec3& p,
                                        const std::vector<index_t>& ball_keep,
                                        const std::vector<index_t>& ball_remove) {
  thread_local std::vector<index_t> ring, unchanged;
  if (!collapse_cavity(keep, ball_remove, ring)) return OpStatus::InvalidArgument;
  unchanged.clear();
  for (index_t t : ball_keep)
    if (local_index(t, remove.id) < 0) unchanged.push_back(t);
  commit_collapse(keep, remove, p, ball_remove, ring, unchanged);
  return OpStatus::Ok;
}

void TetMesh::commit_collapse(Keep keep_vertex, Remove remove_vertex, const Vec3& p,
                              const std::vector<index_t>& ball_remove, const std::vector<index_t>& ring,
                              const std::vector<index_t>& unchanged) {
  const index_t keep = keep_vertex.id, remove = remove_vertex.id;
  // Point data of the merged vertex: linear along the edge at the
  // projection of p (unchanged when p is keep's position).
  if (p != points_[keep]) {
    const Vec3 e = points_[remove] - points_[keep];
    const double len2 = e.squaredNorm();
    double s = len2 > 0 ? (p - points_[keep]).dot(e) / len2 : 0.0;
    s = std::min(1.0, std::max(0.0, s));
    const VertexStencil* stencils[2] = {&vertex_origin_[keep], &vertex_origin_[remove]};
    const double weights[2] = {1.0 - s, s};
    vertex_origin_[keep] = combine_stencils(stencils, weights, 2);
  }
  // The more constrained class survives (rules (D)-(F) keep that vertex).
  vclass_[keep] = std::max(vclass_[keep], vclass_[remove]);
  // A ring tet whose two outer faces are both on the boundary leaves no
  // tet to glue them to: the general cavity replacement handles it.
  const bool in_place = std::none_of(ring.begin(), ring.end(), [&](index_t t) {
    return rec_[t].n[local_index(t, keep)] < 0 && rec_[t].n[local_index(t, remove)] < 0;
  });
  if (in_place) {
    // The tets of ball(remove) off the edge stay in their slots with remove
    // renamed keep (their faces keep their places, so their links hold);
    // each vanishing ring tet glues its two outer faces, (remove, x, y) and
    // (keep, x, y), to each other: no new slots and no face matching.
    touched_.clear();
    for (const index_t t : ring) {
      const TetRecord& R = rec_[t];
      const int ik = local_index(t, keep), ir = local_index(t, remove);
      const index_t across_remove = R.n[ik], across_keep = R.n[ir];
      if (across_remove >= 0) rec_[across_remove >> 2].n[across_remove & 3] = across_keep;
      if (across_keep >= 0) rec_[across_keep >> 2].n[across_keep & 3] = across_remove;
      const index_t survivor = across_remove >= 0 ? across_remove >> 2 : across_keep >> 2;
      for (int i = 0; i < 4; ++i)
        if (i != ik && i != ir) vertex_tet_[R.v[i]] = survivor;
    }
    for (const index_t t : ball_remove) {
      if (local_index(t, keep) >= 0) continue;  // a ring tet
      for (index_t& w : rec_[t].v)
        if (w == remove) w = keep;
      touched_.push_back(t);
    }
    for (const index_t t : ring) delete_tet(t);
  } else {
    scratch_new_.clear();
    scratch_origin_.clear();
    for (const index_t t : ball_remove) {
      if (local_index(t, keep) >= 0) continue;
      Tet T = rec_[t].v;
      for (index_t& w : T)
        if (w == remove) w = keep;
      scratch_new_.push_back(T);
      scratch_origin_.push_back(tet_origin_[t]);
    }
    // The cavity is ball(remove); tets on the edge vanish and their two
    // outer faces are zipped by replace_tets.
    replace_tets(ball_remove, scratch_new_, scratch_origin_, remove, keep);
  }
  points_[keep] = p;
  delete_vertex(remove);
  if (!tet_alive(vertex_tet_[keep]) || local_index(vertex_tet_[keep], keep) < 0)
    vertex_tet_[keep] = !unchanged.empty() ? unchanged.front() : !touched_.empty() ? touched_.front() : kInvalidIndex;
  // Tets of keep's ball that only moved are touched too.
  touched_.insert(touched_.end(), unchanged.begin(), unchanged.end());
}

OpStatus TetMesh::half_edge_collapse_keeping_inverted(Keep keep, Remove remove) {
  if (!allow_inverted_) return OpStatus::InvalidArgument;
  keep_inverted_ = true;
  const OpStatus status = collapse_edge(keep, remove, nullptr);
  keep_inverted_ = false;
  return status;
}

}  // namespace femorph
