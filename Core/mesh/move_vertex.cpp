// Vertex move with the exact orientation test of every tet of its ball: the
// step every smoother (thesis 2.6.1.1, 2.6.5) takes to place a vertex.
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"

namespace femorph {

OpStatus TetMesh::move_vertex(index_t v, const Vec3& p) {
  if (!vertex_alive(v) || !p.allFinite()) return OpStatus::InvalidArgument;
  vertex_ball(v, scratch_ball_);
  const OpStatus s = move_vertex_in_ball(v, p, scratch_ball_);
  if (s == OpStatus::Ok) touched_ = scratch_ball_;
  return s;
}

OpStatus TetMesh::move_vertex_in_ball(index_t v, const Vec3& p, const std::vector<index_t>& ball) {
  if (!vertex_alive(v) || !p.allFinite()) return OpStatus::InvalidArgument;
  for (index_t t : ball) {
    const Tet& T = rec_[t].v;
    const Vec3* q[4];
    for (int i = 0; i < 4; ++i) q[i] = T[i] == v ? &p : &points_[T[i]];
    if (orient3d_sign(*q[0], *q[1], *q[2], *q[3]) <= 0) return OpStatus::Inverted;
  }
  points_[v] = p;
  return OpStatus::Ok;
}

}  // namespace femorph
