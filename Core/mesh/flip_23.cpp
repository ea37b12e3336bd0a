// Flip 2-3, thesis 2.6.5.4 Fig. 2.46: two tets sharing a face become three
// tets sharing the edge between the two opposite vertices.
#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"

namespace femorph {

OpStatus TetMesh::flip_23(index_t t, int f) {
  if (!tet_alive(t) || f < 0 || f > 3) return OpStatus::InvalidArgument;
  const index_t code = rec_[t].n[f];
  if (code < 0) return OpStatus::BoundaryEntity;
  const index_t n = code >> 2;
  const index_t d = rec_[t].v[f];        // apex on t's side
  const index_t e = rec_[n].v[code & 3]; // apex on n's side
  // Replacing each face vertex of n by d gives the three new tets; they are
  // all positive exactly when segment (d, e) crosses the face's interior.
  scratch_new_.clear();
  scratch_origin_.clear();
  for (int k = 0; k < 3; ++k) {
    Tet T = rec_[t].v;
    const index_t u = T[kTetFace[f][k]];
    T = rec_[n].v;
    for (int i = 0; i < 4; ++i)
      if (T[i] == u) T[i] = d;
    if (orient3d_sign(points_[T[0]], points_[T[1]], points_[T[2]], points_[T[3]]) <= 0) return OpStatus::Inverted;
    scratch_new_.push_back(T);
    scratch_origin_.push_back(k == 0 ? tet_origin_[t] : tet_origin_[n]);
  }
  // Topology after geometry: the edge search walks a ball.
  if (has_edge(d, e)) return OpStatus::DuplicateEntity;
  std::vector<index_t>& cavity = scratch_ball_;
  cavity.assign({t, n});
  replace_tets(cavity, scratch_new_, scratch_origin_, kInvalidIndex, kInvalidIndex);
  return OpStatus::Ok;
}

}  // namespace femorph
