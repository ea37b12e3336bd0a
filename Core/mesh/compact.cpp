// TetMesh::compact: the live mesh renumbered densely for output, with the
// provenance (tet_origin, vertex_origin) and face regions that let the
// filters carry attribute data over (docs/ARCHITECTURE.md).
#include "mesh/tet_mesh.h"

namespace femorph {

CompactMesh TetMesh::compact() const {
  CompactMesh out;
  out.vertex_map.assign(points_.size(), kInvalidIndex);
  for (index_t v = 0; v < vertex_slots(); ++v) {
    if (!vertex_alive(v)) continue;
    out.vertex_map[v] = static_cast<index_t>(out.points.size());
    out.points.push_back(points_[v]);
    out.vertex_classes.push_back(vclass_[v]);
    out.vertex_origin.push_back(vertex_origin_[v]);
  }
  const std::size_t nt = live_tets();
  out.tets.reserve(nt);
  out.face_regions.reserve(nt);
  out.tet_origin.reserve(nt);
  for (index_t t = 0; t < tet_slots(); ++t) {
    if (!tet_alive(t)) continue;
    Tet T, R;
    for (int i = 0; i < 4; ++i) {
      T[i] = out.vertex_map[rec_[t].v[i]];
      R[i] = face_region(t, i);
    }
    out.tets.push_back(T);
    out.face_regions.push_back(R);
    out.tet_origin.push_back(tet_origin_[t]);
  }
  return out;
}

std::vector<Tet> live_tet_list(const TetMesh& mesh) {
  std::vector<Tet> tets;
  tets.reserve(mesh.live_tets());
  for (index_t t = 0; t < mesh.tet_slots(); ++t)
    if (mesh.tet_alive(t)) tets.push_back(mesh.tet(t));
  return tets;
}

}  // namespace femorph
