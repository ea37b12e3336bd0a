// TetMesh::check_consistency: every invariant the mesh's operations rely on,
// checked from scratch in O(#T), for tests.
#include "mesh/tet_mesh.h"

#include "mesh/tet_mesh_internal.h"

#include <sstream>
#include <string>

namespace femorph {

Status TetMesh::check_consistency() const {
  std::ostringstream err;
  std::size_t errors = 0;
  auto note = [&](const std::string& m) {
    if (errors++ < 10) err << m << "\n";
  };
  for (index_t t = 0; t < tet_slots(); ++t) {
    if (!tet_alive(t)) continue;
    const Tet& T = rec_[t].v;
    for (int i = 0; i < 4; ++i) {
      if (!vertex_alive(T[i])) note("tet " + std::to_string(t) + " uses dead vertex " + std::to_string(T[i]));
      for (int j = 0; j < i; ++j)
        if (T[i] == T[j]) note("tet " + std::to_string(t) + " repeats a vertex");
    }
    const int o = orientation(t);
    if (o < 0 || (o == 0 && !allow_inverted_))
      if (!allow_inverted_) note("tet " + std::to_string(t) + " is not positively oriented");
    for (int f = 0; f < 4; ++f) {
      const index_t code = rec_[t].n[f];
      if (code < 0) continue;
      const index_t n = code >> 2, g = code & 3;
      if (!tet_alive(n)) {
        note("tet " + std::to_string(t) + " face " + std::to_string(f) + " points to dead tet");
        continue;
      }
      if (rec_[n].n[g] != 4 * t + f) note("adjacency not symmetric at tet " + std::to_string(t));
      index_t a[3], b[3];
      for (int k = 0; k < 3; ++k) {
        a[k] = T[kTetFace[f][k]];
        b[k] = rec_[n].v[kTetFace[g][k]];
      }
      const bool oa = internal::sort3_parity(a), ob = internal::sort3_parity(b);
      if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2])
        note("tet " + std::to_string(t) + " face " + std::to_string(f) + " does not match its neighbour's face");
      else if (oa == ob)
        note("tet " + std::to_string(t) + " and its neighbour disagree on orientation");
    }
  }
  std::vector<index_t> ball;
  for (index_t v = 0; v < vertex_slots(); ++v) {
    if (!vertex_alive(v)) continue;
    const index_t t = vertex_tet_[v];
    if (!tet_alive(t) || local_index(t, v) < 0) note("vertex " + std::to_string(v) + " has a stale incident tet");
  }
  // Every live tet's vertices reach it through their ball walk.
  std::vector<index_t> count(points_.size(), 0);
  for (index_t t = 0; t < tet_slots(); ++t)
    if (tet_alive(t))
      for (index_t w : rec_[t].v) ++count[w];
  for (index_t v = 0; v < vertex_slots(); ++v) {
    if (!vertex_alive(v)) {
      if (count[v]) note("dead vertex " + std::to_string(v) + " is used by tets");
      continue;
    }
    if (count[v] == 0) note("vertex " + std::to_string(v) + " is alive but used by no tet");
    vertex_ball(v, ball);
    if (static_cast<index_t>(ball.size()) != count[v])
      note("ball walk of vertex " + std::to_string(v) + " misses tets");
  }
  for (index_t t : free_tets_)
    if (tet_alive(t)) note("free tet " + std::to_string(t) + " is alive");
  for (index_t v : free_vertices_)
    if (vertex_alive(v)) note("free vertex " + std::to_string(v) + " is alive");
  if (errors) return Status::failure(std::to_string(errors) + " inconsistencies:\n" + err.str());
  return Status::success();
}

}  // namespace femorph
