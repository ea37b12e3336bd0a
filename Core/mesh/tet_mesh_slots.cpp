// TetMesh's slots: tets and vertices are taken from the free lists before
// the arrays grow, and a deleted one is tombstoned (first id -1) and listed
// free; memory_bytes() sums the arrays' capacity.
#include "mesh/tet_mesh.h"

namespace femorph {

index_t TetMesh::new_tet(const Tet& vertices, index_t origin) {
  index_t t;
  if (!free_tets_.empty()) {
    t = free_tets_.back();
    free_tets_.pop_back();
    rec_[t].v = vertices;
    rec_[t].n = Tet{{-1, -1, -1, -1}};
    tet_origin_[t] = origin;
  } else {
    t = static_cast<index_t>(rec_.size());
    rec_.push_back(TetRecord{vertices, Tet{{-1, -1, -1, -1}}});
    tet_origin_.push_back(origin);
  }
  return t;
}

void TetMesh::delete_tet(index_t t) {
  rec_[t].v[0] = kInvalidIndex;
  free_tets_.push_back(t);
}

index_t TetMesh::new_vertex(const Vec3& p, const VertexStencil& origin, VertexClass c) {
  index_t v;
  if (!free_vertices_.empty()) {
    v = free_vertices_.back();
    free_vertices_.pop_back();
    points_[v] = p;
    vertex_origin_[v] = origin;
    vclass_[v] = c;
  } else {
    v = static_cast<index_t>(points_.size());
    points_.push_back(p);
    vertex_origin_.push_back(origin);
    vclass_.push_back(c);
    vertex_tet_.push_back(kInvalidIndex);
  }
  return v;
}

void TetMesh::delete_vertex(index_t v) {
  vertex_tet_[v] = kInvalidIndex;
  free_vertices_.push_back(v);
}

std::size_t TetMesh::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(points_) + bytes(rec_) + bytes(vertex_tet_) + bytes(vclass_) +
         bytes(tet_origin_) + bytes(vertex_origin_) + bytes(free_tets_) + bytes(free_vertices_) +
         bytes(tet_marks_.stamp) + bytes(link_stamps_.stamp) + bytes(scratch_ring_) + bytes(scratch_verts_) +
         bytes(scratch_ball_) + bytes(scratch_ball2_) + bytes(scratch_new_) + bytes(scratch_origin_) + bytes(touched_);
}

}  // namespace femorph
