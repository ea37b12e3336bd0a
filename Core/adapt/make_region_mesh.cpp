// The deformed region as a mesh of its own: the adaptation and Improve then
// touch only its tets (locality: their cost does not grow with the space
// mesh), and the result is spliced back with TetMesh::replace_cavity.
#include "adapt/adapt.h"

namespace femorph {

Status make_region_mesh(const TetMesh& mesh, const std::vector<index_t>& region, RegionMesh& out) {
  out.global_vertex.clear();
  out.global_tet = region;
  std::vector<index_t> local(static_cast<std::size_t>(mesh.vertex_slots()), kInvalidIndex);
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  tets.reserve(region.size());
  for (const index_t t : region) {
    Tet T = mesh.tet(t);
    for (index_t& v : T) {
      if (local[v] < 0) {
        local[v] = static_cast<index_t>(out.global_vertex.size());
        out.global_vertex.push_back(v);
        points.push_back(mesh.point(v));
      }
      v = local[v];
    }
    tets.push_back(T);
  }
  BuildOptions bo;
  bo.allow_inverted = true;
  bo.allow_degenerate = true;
  const Status s = out.mesh.build(std::move(points), std::move(tets), bo);
  if (!s) return Status::failure("the deformed region is not a valid submesh: " + s.message);
  return Status::success();
}

}  // namespace femorph
