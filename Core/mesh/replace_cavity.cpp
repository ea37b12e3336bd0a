// A cavity replaced by tets made elsewhere (Adapt's deformed region, adapted
// as a mesh of its own, spliced back into the space mesh). The boundaries
// must match face for face: the outside of the cavity does not change.
#include "mesh/tet_mesh.h"

#include <algorithm>
#include <array>

namespace femorph {

Status TetMesh::replace_cavity(const std::vector<index_t>& old_tets, const std::vector<Tet>& new_tets,
                               const std::vector<index_t>& new_origins, const std::vector<Vec3>& new_points,
                               const std::vector<VertexStencil>& new_point_origins, std::vector<index_t>* created,
                               const std::vector<std::array<index_t, 3>>* given_boundary) {
  if (new_origins.size() != new_tets.size() || new_point_origins.size() != new_points.size())
    return Status::failure("replace_cavity: array sizes differ");
  // Boundary faces (sorted ids -> count) of the old and of the new tets, new
  // points named by their negative ids.
  using Key = std::array<index_t, 3>;
  const auto key = [](index_t a, index_t b, index_t c) {
    Key k{{a, b, c}};
    std::sort(k.begin(), k.end());
    return k;
  };
  std::vector<Key> cavity_faces, new_faces;
  for (const index_t t : old_tets)
    if (!tet_alive(t)) return Status::failure("replace_cavity: a cavity tet is not alive");
  const std::uint16_t in_cavity = next_tet_mark();
  for (const index_t t : old_tets) tet_marks_.stamp[t] = in_cavity;
  for (const index_t t : old_tets)
    for (int f = 0; f < 4; ++f) {
      const index_t code = rec_[t].n[f];
      if (code >= 0 && tet_marks_.stamp[code >> 2] == in_cavity) continue;
      const Tet& T = rec_[t].v;
      cavity_faces.push_back(key(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]));
    }
  std::sort(cavity_faces.begin(), cavity_faces.end());
  std::vector<Key> new_boundary;
  if (given_boundary) {
    for (const auto& f : *given_boundary) new_boundary.push_back(key(f[0], f[1], f[2]));
    std::sort(new_boundary.begin(), new_boundary.end());
  } else {
    for (const Tet& T : new_tets)
      for (int f = 0; f < 4; ++f) new_faces.push_back(key(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]));
    std::sort(new_faces.begin(), new_faces.end());
    for (std::size_t i = 0; i < new_faces.size();) {
      std::size_t j = i;
      while (j < new_faces.size() && new_faces[j] == new_faces[i]) ++j;
      if (j - i > 2) return Status::failure("replace_cavity: a face of the new tets is shared by more than two");
      if (j - i == 1) new_boundary.push_back(new_faces[i]);
      i = j;
    }
  }
  if (new_boundary != cavity_faces)
    return Status::failure("replace_cavity: the new tets' boundary differs from the cavity's");

  std::vector<index_t> ids(new_points.size());
  for (std::size_t i = 0; i < new_points.size(); ++i)
    ids[i] = new_vertex(new_points[i], new_point_origins[i], VertexClass::Inner);
  std::vector<index_t> cavity_vertices;
  for (const index_t t : old_tets)
    for (const index_t v : rec_[t].v) cavity_vertices.push_back(v);
  std::vector<Tet> tets = new_tets;
  for (Tet& T : tets)
    for (index_t& v : T)
      if (v < 0) v = ids[static_cast<std::size_t>(-1 - v)];
  // replace_tets links by face keys; the check above made them match.
  std::vector<index_t> sorted_old = old_tets;
  replace_tets(sorted_old, tets, new_origins, kInvalidIndex, kInvalidIndex);
  // Cavity vertices no new tet uses (and no outer tet: they were inside).
  std::vector<char> kept(points_.size(), 0);
  for (const Key& k : cavity_faces)
    for (const index_t v : k) kept[v] = 1;
  for (const Tet& T : tets)
    for (const index_t v : T) kept[v] = 1;
  for (const index_t v : cavity_vertices)
    if (!kept[v] && vertex_tet_[v] != kInvalidIndex) {
      kept[v] = 1;  // once
      delete_vertex(v);
    }
  if (created) *created = std::move(ids);
  return Status::success();
}

}  // namespace femorph
