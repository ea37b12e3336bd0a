// TetMesh's element access that is not inline, and the names of OpStatus.
// Where the rest of TetMesh lives: see the file list in tet_mesh.h.
#include "mesh/tet_mesh.h"

#include "geometry/predicates.h"
#include "mesh/tet_mesh_internal.h"

namespace femorph {

const char* to_string(OpStatus status) {
  switch (status) {
    case OpStatus::Ok: return "ok";
    case OpStatus::InvalidArgument: return "invalid argument (dead element or no such edge/face)";
    case OpStatus::BoundaryEntity: return "the edge or face lies on the boundary";
    case OpStatus::WrongValence: return "wrong number of tets around the edge";
    case OpStatus::Inverted: return "a resulting tet would be inverted or flat";
    case OpStatus::DuplicateEntity: return "the new edge or face already exists";
    case OpStatus::LinkCondition: return "the link condition fails (topology would change)";
    case OpStatus::ForbiddenByRule: return "forbidden by the collapse rules of thesis Fig. 2.37";
  }
  return "unknown";
}

void TetMesh::set_face_region(index_t t, int f, index_t region) {
  if (rec_[t].n[f] < 0) rec_[t].n[f] = internal::boundary_code(region);
}

int TetMesh::local_index(index_t t, index_t v) const {
  if (t < 0) return -1;
  const Tet& T = rec_[t].v;
  for (int i = 0; i < 4; ++i)
    if (T[i] == v) return i;
  return -1;
}

int TetMesh::orientation(index_t t) const {
  const Tet& T = rec_[t].v;
  return orient3d_sign(points_[T[0]], points_[T[1]], points_[T[2]], points_[T[3]]);
}

}  // namespace femorph
