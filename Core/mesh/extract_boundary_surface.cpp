// extract_boundary_surface: the boundary faces of a tet mesh as an outward
// SurfaceMesh, for the segmentation (thesis 2.4) to work on; or the part of
// it around some vertices, for a local deformation (2.5.4).
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"

#include <string>

namespace femorph {

namespace {

/// The boundary faces of `mesh` (all, or those with a vertex in `mask`: an
/// open surface) as a SurfaceMesh.
Status boundary_faces(const TetMesh& mesh, const std::vector<std::uint8_t>* mask, SurfaceMesh& out,
                      SurfaceReport* report) {
  const index_t nt = mesh.tet_slots();
  const index_t nv = mesh.vertex_slots();

  // Boundary faces in (tet, local face) order, as tet mesh vertex ids; the
  // order kTetFace gives faces outward normals on positive tets.
  std::vector<Tri> triangles;
  std::vector<index_t> source_face;
  std::vector<index_t> surface_id(static_cast<std::size_t>(nv), kInvalidIndex);
  for (index_t t = 0; t < nt; ++t) {
    if (!mesh.tet_alive(t)) continue;
    const Tet& tet = mesh.tet(t);
    for (int f = 0; f < 4; ++f) {
      if (!mesh.is_boundary_face(t, f)) continue;
      const Tri tri{{tet[kTetFace[f][0]], tet[kTetFace[f][1]], tet[kTetFace[f][2]]}};
      if (mask && !(*mask)[tri[0]] && !(*mask)[tri[1]] && !(*mask)[tri[2]]) continue;
      for (index_t v : tri) surface_id[v] = 0;  // marked; numbered below
      triangles.push_back(tri);
      source_face.push_back(4 * t + f);
    }
  }
  if (triangles.empty()) {
    out = SurfaceMesh();
    if (report) *report = SurfaceReport();
    return Status::failure(mask ? "the tet mesh has no boundary faces there" : "the tet mesh has no boundary faces");
  }

  // Surface vertices numbered compactly in ascending tet mesh id.
  std::vector<Vec3> points;
  std::vector<index_t> source_vertex;
  for (index_t v = 0; v < nv; ++v) {
    if (surface_id[v] == kInvalidIndex) continue;
    surface_id[v] = static_cast<index_t>(points.size());
    points.push_back(mesh.point(v));
    source_vertex.push_back(v);
  }
  for (Tri& tri : triangles)
    for (index_t& v : tri) v = surface_id[v];

  const Status built = build_surface_mesh(std::move(points), std::move(triangles), out, mask != nullptr, report);
  if (!built) return Status::failure("boundary of the tet mesh: " + built.message);
  out.source_vertex = std::move(source_vertex);
  out.source_face = std::move(source_face);
  return Status::success();
}

}  // namespace

Status extract_boundary_surface(const TetMesh& mesh, SurfaceMesh& out, SurfaceReport* report) {
  return boundary_faces(mesh, nullptr, out, report);
}

Status extract_boundary_surface_near(const TetMesh& mesh, const std::vector<std::uint8_t>& vertices, SurfaceMesh& out) {
  return boundary_faces(mesh, &vertices, out, nullptr);
}

}  // namespace femorph
