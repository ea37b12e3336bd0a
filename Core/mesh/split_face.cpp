// Face split, thesis 2.6.1.3 Fig. 2.35 (b).
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"
#include "mesh/vertex_stencil.h"

#include <Eigen/Geometry>

namespace femorph {

OpStatus TetMesh::split_face(index_t t, int f, const Vec3* position, index_t* new_vertex_out) {
  if (!tet_alive(t) || f < 0 || f > 3) return OpStatus::InvalidArgument;
  const index_t face[3] = {rec_[t].v[kTetFace[f][0]], rec_[t].v[kTetFace[f][1]], rec_[t].v[kTetFace[f][2]]};
  const Vec3& x0 = points_[face[0]];
  const Vec3& x1 = points_[face[1]];
  const Vec3& x2 = points_[face[2]];
  const Vec3 p = position ? *position : Vec3((x0 + x1 + x2) / 3.0);
  if (!p.allFinite()) return OpStatus::InvalidArgument;

  // The one or two tets on the face; each becomes three by replacing one face
  // vertex at a time with the new vertex (same local slots, same convention).
  std::vector<index_t>& cavity = scratch_ball_;
  cavity.clear();
  cavity.push_back(t);
  const bool boundary = rec_[t].n[f] < 0;
  if (!boundary) cavity.push_back(rec_[t].n[f] >> 2);
  for (index_t c : cavity)
    for (index_t replaced : face) {
      const Tet& T = rec_[c].v;
      const Vec3* q[4];
      for (int i = 0; i < 4; ++i) q[i] = T[i] == replaced ? &p : &points_[T[i]];
      if (orient3d_sign(*q[0], *q[1], *q[2], *q[3]) <= 0) return OpStatus::Inverted;
    }

  // Point data: barycentric weights of p's projection on the face.
  double w[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const Vec3 n = (x1 - x0).cross(x2 - x0);
  const double area2 = n.squaredNorm();
  if (area2 > 0) {
    w[0] = (x1 - p).cross(x2 - p).dot(n) / area2;
    w[1] = (x2 - p).cross(x0 - p).dot(n) / area2;
    w[2] = 1.0 - w[0] - w[1];
  }
  const VertexStencil* stencils[3] = {&vertex_origin_[face[0]], &vertex_origin_[face[1]], &vertex_origin_[face[2]]};
  const index_t m = new_vertex(p, combine_stencils(stencils, w, 3), boundary ? VertexClass::Surface : VertexClass::Inner);

  scratch_new_.clear();
  scratch_origin_.clear();
  for (index_t c : cavity)
    for (index_t replaced : face) {
      Tet T = rec_[c].v;
      for (int i = 0; i < 4; ++i)
        if (T[i] == replaced) T[i] = m;
      scratch_new_.push_back(T);
      scratch_origin_.push_back(tet_origin_[c]);
    }
  replace_tets(cavity, scratch_new_, scratch_origin_, kInvalidIndex, kInvalidIndex);
  if (new_vertex_out) *new_vertex_out = m;
  return OpStatus::Ok;
}

}  // namespace femorph
