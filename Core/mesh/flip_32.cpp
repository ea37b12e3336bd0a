// Flip 3-2, thesis 2.6.5.4 Fig. 2.46: the inverse of flip 2-3. An interior
// edge with exactly three tets around it becomes the triangle of the three
// ring vertices, with one tet on each side.
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"

namespace femorph {

OpStatus TetMesh::flip_32(index_t a, index_t b, index_t hint) {
  std::vector<index_t>& ring = scratch_ball_;
  std::vector<index_t>& c = scratch_ball2_;
  bool boundary = false;
  if (!edge_ring_with_vertices(a, b, ring, c, &boundary, hint)) return OpStatus::InvalidArgument;
  if (boundary) return OpStatus::BoundaryEntity;
  if (ring.size() != 3) return OpStatus::WrongValence;

  // ring[0] holds a, b, c0, c1: replacing b (then a) by c2 gives the two new
  // tets with the convention preserved.
  scratch_new_.clear();
  scratch_origin_.clear();
  for (index_t replaced : {b, a}) {
    Tet T = rec_[ring[0]].v;
    for (int i = 0; i < 4; ++i)
      if (T[i] == replaced) T[i] = c[2];
    if (orient3d_sign(points_[T[0]], points_[T[1]], points_[T[2]], points_[T[3]]) <= 0) return OpStatus::Inverted;
    scratch_new_.push_back(T);
    scratch_origin_.push_back(tet_origin_[ring[replaced == b ? 0 : 1]]);
  }
  // Topology after geometry: the face search walks a ball.
  if (find_face(c[0], c[1], c[2]) >= 0) return OpStatus::DuplicateEntity;
  replace_tets(ring, scratch_new_, scratch_origin_, kInvalidIndex, kInvalidIndex);
  return OpStatus::Ok;
}

}  // namespace femorph
