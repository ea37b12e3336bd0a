// Edge split, thesis 2.6.1.3 Fig. 2.35 (a): the vertex insertion used for
// density and accuracy control (2.6.3, 2.6.4) and by the degenerate-element
// removal (2.6.2).
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"
#include "mesh/vertex_stencil.h"

namespace femorph {

OpStatus TetMesh::split_edge(index_t a, index_t b, const Vec3* position, index_t* new_vertex_out, index_t hint) {
  bool boundary = false;
  if (!edge_ring_with_vertices(a, b, scratch_ball_, scratch_ball2_, &boundary, hint)) return OpStatus::InvalidArgument;
  return split_edge(a, b, position, new_vertex_out, scratch_ball_, scratch_ball2_, boundary);
}

OpStatus TetMesh::split_edge(index_t a, index_t b, const Vec3* position, index_t* new_vertex_out,
                             const std::vector<index_t>& ring, const std::vector<index_t>& c, bool boundary) {
  if (ring.empty() || !vertex_alive(a) || !vertex_alive(b)) return OpStatus::InvalidArgument;
  const Vec3 p = position ? *position : Vec3(0.5 * (points_[a] + points_[b]));
  if (!p.allFinite()) return OpStatus::InvalidArgument;

  // Each tet (.. a .. b ..) becomes two: b replaced by m, and a replaced by m.
  // Keeping the local slots keeps the orientation convention; the geometry is
  // checked exactly because `position` may lie off the segment.
  auto positive_with = [&](const Tet& T, index_t replaced) {
    const Vec3* q[4];
    for (int i = 0; i < 4; ++i) q[i] = T[i] == replaced ? &p : &points_[T[i]];
    return orient3d_sign(*q[0], *q[1], *q[2], *q[3]) > 0;
  };
  for (index_t t : ring)
    if (!positive_with(rec_[t].v, a) || !positive_with(rec_[t].v, b)) return OpStatus::Inverted;

  // Point data: linear along the edge at the projection of p.
  const Vec3 ab = points_[b] - points_[a];
  const double len2 = ab.squaredNorm();
  double s = len2 > 0 ? (p - points_[a]).dot(ab) / len2 : 0.5;
  s = std::min(1.0, std::max(0.0, s));
  const VertexStencil* stencils[2] = {&vertex_origin_[a], &vertex_origin_[b]};
  const double weights[2] = {1.0 - s, s};
  VertexClass cls = VertexClass::Inner;
  if (boundary) cls = open_ring_on_curve(ring, c) ? VertexClass::Curve : VertexClass::Surface;
  const index_t m = new_vertex(p, combine_stencils(stencils, weights, 2), cls);

  // Each ring tet T_i keeps its slot as A_i = T_i with b -> m, and a new
  // slot B_i = T_i with a -> m is added. Same local slots, so adjacency is
  // direct (no face matching):
  //   A_i keeps T_i's neighbours, except across face (m, c_i, c_i+1), which
  //   is B_i's; B_i gets T_i's outer neighbour across the face opposite a, A_i
  //   across the face opposite b, and B_j wherever T_i had the ring tet T_j.
  const std::size_t n = ring.size();
  thread_local std::vector<index_t> b_slot;
  b_slot.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const index_t t = ring[i];
    Tet tb = rec_[t].v;
    for (index_t& w : tb)
      if (w == a) w = m;
    b_slot[i] = new_tet(tb, tet_origin_[t]);
  }
  touched_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const index_t t = ring[i], u = b_slot[i];
    TetRecord& A = rec_[t];
    TetRecord& B = rec_[u];
    const int la = local_index(t, a), lb = local_index(t, b);
    for (int f = 0; f < 4; ++f) {
      const index_t code = A.n[f];
      if (f == la) {
        // B_i's outer neighbour across the face opposite a (same face).
        B.n[f] = code;
        if (code >= 0) rec_[code >> 2].n[code & 3] = 4 * u + f;
      } else if (f == lb) {
        // A_i keeps the outer neighbour across the face opposite b.
      } else if (code < 0) {
        B.n[f] = code;  // a boundary face of the ring's end, halved
      } else {
        // Across a face holding the edge: the ring tet T_j, whose B_j is B_i's.
        const index_t tj = code >> 2;
        std::size_t j = 0;
        while (ring[j] != tj) ++j;
        B.n[f] = 4 * b_slot[j] + (code & 3);
      }
    }
    A.v[lb] = m;
    A.n[la] = 4 * u + lb;
    B.n[lb] = 4 * t + la;
    touched_.push_back(t);
    touched_.push_back(u);
  }
  vertex_tet_[m] = ring[0];
  vertex_tet_[b] = b_slot[0];
  if (new_vertex_out) *new_vertex_out = m;
  return OpStatus::Ok;
}

}  // namespace femorph
