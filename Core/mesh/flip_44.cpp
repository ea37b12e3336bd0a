// Flip 4-4, thesis 2.6.5.4 Fig. 2.46: the interior edge (a, b) of an
// octahedron of four tets is swapped for one of the two other diagonals.
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"

namespace femorph {

OpStatus TetMesh::flip_44(index_t a, index_t b, int diagonal, index_t hint) {
  if (diagonal != 0 && diagonal != 1) return OpStatus::InvalidArgument;
  std::vector<index_t>& ring = scratch_ball_;
  std::vector<index_t>& c = scratch_ball2_;
  bool boundary = false;
  if (!edge_ring_with_vertices(a, b, ring, c, &boundary, hint)) return OpStatus::InvalidArgument;
  if (boundary) return OpStatus::BoundaryEntity;
  if (ring.size() != 4) return OpStatus::WrongValence;
  // New edge (c[k], c[k + 2]); ring[k] holds c[k], c[k+1] and ring[k+2] holds
  // c[k+2], c[k+3]. In each, replacing b (then a) by the far diagonal vertex
  // gives two of the four new tets.
  const int k = diagonal;
  scratch_new_.clear();
  scratch_origin_.clear();
  const std::pair<index_t, index_t> sources[2] = {{ring[k], c[k + 2]}, {ring[k + 2], c[k]}};
  for (const auto& [t, far] : sources)
    for (index_t replaced : {b, a}) {
      Tet T = rec_[t].v;
      for (int i = 0; i < 4; ++i)
        if (T[i] == replaced) T[i] = far;
      if (orient3d_sign(points_[T[0]], points_[T[1]], points_[T[2]], points_[T[3]]) <= 0)
        return OpStatus::Inverted;
      scratch_new_.push_back(T);
      scratch_origin_.push_back(tet_origin_[t]);
    }
  // Topology after geometry: the edge search walks a ball.
  if (has_edge(c[k], c[k + 2])) return OpStatus::DuplicateEntity;
  replace_tets(ring, scratch_new_, scratch_origin_, kInvalidIndex, kInvalidIndex);
  return OpStatus::Ok;
}

}  // namespace femorph
