// Edge removal into a fan from one ring vertex: a split of the edge and the
// collapse of the new vertex into that ring vertex in one step (the
// density control's merge of a midpoint, control_mesh_density.cpp).
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"

namespace femorph {

OpStatus TetMesh::flip_edge_to_fan(index_t a, index_t b, index_t apex, const std::vector<index_t>& ring,
                                   const std::vector<index_t>& c, bool check_edges) {
  const std::size_t n = ring.size();
  if (n < 3 || c.size() != n || !vertex_alive(a) || !vertex_alive(b)) return OpStatus::InvalidArgument;
  std::size_t k = 0;  // c[k] == apex: ring[k - 1] and ring[k] hold it
  while (k < n && c[k] != apex) ++k;
  if (k == n) return OpStatus::InvalidArgument;
  const auto holds_apex = [&](std::size_t i) { return i == k || (i + 1) % n == k; };
  scratch_new_.clear();
  scratch_origin_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (holds_apex(i)) continue;
    for (const index_t replaced : {b, a}) {
      Tet T = rec_[ring[i]].v;
      for (index_t& w : T)
        if (w == replaced) w = apex;
      if (orient3d_sign(points_[T[0]], points_[T[1]], points_[T[2]], points_[T[3]]) <= 0) return OpStatus::Inverted;
      scratch_new_.push_back(T);
      scratch_origin_.push_back(tet_origin_[ring[i]]);
    }
  }
  // The new edges: apex to the ring vertices other than itself and its two
  // ring neighbours; with three, none, but the new face of the ring's
  // vertices (as in flip 3-2). Topology after geometry: the searches walk
  // a ball.
  if (check_edges) {
    if (n == 3 && find_face(c[0], c[1], c[2]) >= 0) return OpStatus::DuplicateEntity;
    for (std::size_t j = 0; j < n; ++j)
      if (j != k && j != (k + 1) % n && (j + 1) % n != k && has_edge(apex, c[j])) return OpStatus::DuplicateEntity;
  }
  replace_tets(ring, scratch_new_, scratch_origin_, kInvalidIndex, kInvalidIndex);
  return OpStatus::Ok;
}

}  // namespace femorph
