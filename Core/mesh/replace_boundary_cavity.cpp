// A cavity on the domain's boundary replaced by tets whose boundary differs
// there (Adapt's assembly mode, thesis 3.7.4: two parts' contact faces, on
// the boundary while the parts are apart, become one shared interface).
// The faces the cavity shares with the kept tets must match face for face;
// the faces on the domain's boundary may change.
#include "mesh/tet_mesh.h"

#include <algorithm>
#include <array>

namespace femorph {

Status TetMesh::replace_boundary_cavity(const std::vector<index_t>& old_tets, const std::vector<Tet>& new_tets,
                                        const std::vector<index_t>& new_origins, const std::vector<Vec3>& new_points,
                                        const std::vector<VertexStencil>& new_point_origins,
                                        std::vector<index_t>* created) {
  if (new_origins.size() != new_tets.size() || new_point_origins.size() != new_points.size())
    return Status::failure("replace_boundary_cavity: array sizes differ");
  using Key = std::array<index_t, 3>;
  const auto key = [](index_t a, index_t b, index_t c) {
    Key k{{a, b, c}};
    std::sort(k.begin(), k.end());
    return k;
  };
  for (const index_t t : old_tets)
    if (!tet_alive(t)) return Status::failure("replace_boundary_cavity: a cavity tet is not alive");
  const std::uint16_t in_cavity = next_tet_mark();
  for (const index_t t : old_tets) tet_marks_.stamp[t] = in_cavity;
  // The cavity's faces against kept tets.
  std::vector<Key> inner_faces;
  for (const index_t t : old_tets)
    for (int f = 0; f < 4; ++f) {
      const index_t code = rec_[t].n[f];
      if (code < 0 || tet_marks_.stamp[code >> 2] == in_cavity) continue;
      const Tet& T = rec_[t].v;
      inner_faces.push_back(key(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]));
    }
  std::sort(inner_faces.begin(), inner_faces.end());
  std::vector<Key> faces;
  for (const Tet& T : new_tets)
    for (int f = 0; f < 4; ++f) faces.push_back(key(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]));
  std::sort(faces.begin(), faces.end());
  std::vector<Key> boundary;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i > 2) return Status::failure("replace_boundary_cavity: a face of the new tets is shared by more than two");
    if (j - i == 1) boundary.push_back(faces[i]);
    i = j;
  }
  if (!std::includes(boundary.begin(), boundary.end(), inner_faces.begin(), inner_faces.end()))
    return Status::failure("replace_boundary_cavity: the new tets do not keep the cavity's faces with the kept tets");

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
  replace_tets(old_tets, tets, new_origins, kInvalidIndex, kInvalidIndex);
  // A face on the domain's boundary that becomes a face between two new
  // tets (two parts' surfaces made one interface) met three slots in
  // replace_tets, which linked one new face with the old boundary face:
  // the new tets' boundary faces that pair up are linked here.
  {
    std::vector<std::pair<Key, index_t>> open;
    for (const index_t t : touched_)
      for (int f = 0; f < 4; ++f)
        if (rec_[t].n[f] < 0) {
          const Tet& T = rec_[t].v;
          open.push_back({key(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]), 4 * t + f});
        }
    std::sort(open.begin(), open.end());
    for (std::size_t i = 0; i + 1 < open.size(); ++i)
      if (open[i].first == open[i + 1].first) {
        const index_t a = open[i].second, b = open[i + 1].second;
        rec_[a >> 2].n[a & 3] = b;
        rec_[b >> 2].n[b & 3] = a;
        ++i;
      }
  }
  // Cavity vertices no new tet uses go (a vertex a kept tet uses is on a
  // face between the cavity and the kept tets: its ball is face-connected).
  std::vector<char> kept(points_.size(), 0);
  for (const Key& k : inner_faces)
    for (const index_t v : k) kept[v] = 1;
  for (const Tet& T : tets)
    for (const index_t v : T) kept[v] = 1;
  for (const index_t v : cavity_vertices)
    if (!kept[v] && vertex_tet_[v] != kInvalidIndex) {
      kept[v] = 1;  // once
      delete_vertex(v);
    }
  // The new tets' vertices: on the boundary or inside, as their balls say.
  std::vector<index_t> ball;
  std::vector<char> seen(points_.size(), 0);
  for (const Tet& T : tets)
    for (const index_t v : T) {
      if (seen[v]) continue;
      seen[v] = 1;
      vertex_ball(v, ball);
      vclass_[v] = classify_ball(v, ball);
    }
  if (created) *created = std::move(ids);
  return Status::success();
}

}  // namespace femorph
