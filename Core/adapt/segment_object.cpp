// The objects' surface information for contact (thesis 3.4.2: "a mesh
// segmentation method proposed in section 2.4 is applied to each object mesh
// as a preprocessing"): each object's boundary, segmented into analytic
// regions whose fits later tell which faces of two objects lie on one
// surface.
#include "adapt/contact.h"

#include "mesh/surface_mesh.h"
#include "segment/segmentation.h"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace femorph {

std::vector<ObjectBoundary> object_boundaries(const TetMesh& mesh, const std::vector<int>& material_by_origin) {
  std::map<int, ObjectBoundary> by_material;
  const auto material_of = [&](index_t t) {
    const index_t o = mesh.tet_origin(t);
    return o >= 0 && o < static_cast<index_t>(material_by_origin.size()) ? material_by_origin[o] : 0;
  };
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const int m = material_of(t);
    if (m <= 0) continue;
    const Tet& T = mesh.tet(t);
    for (int f = 0; f < 4; ++f) {
      const index_t n = mesh.adjacency(t, f);
      const index_t nt = n >= 0 ? n / 4 : kInvalidIndex;
      if (nt >= 0 && material_of(nt) == m) continue;
      ObjectBoundary& b = by_material[m];
      b.material = m;
      b.faces.push_back({{T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]}});
    }
  }
  std::vector<ObjectBoundary> out;
  for (auto& [m, b] : by_material) out.push_back(std::move(b));
  return out;
}

Status segment_object(const std::vector<Vec3>& points, const ObjectBoundary& boundary, ObjectSurfaceInfo& out) {
  out = ObjectSurfaceInfo();
  out.material = boundary.material;
  std::unordered_map<index_t, index_t> local;
  std::vector<Vec3> p;
  std::vector<Tri> tris;
  tris.reserve(boundary.faces.size());
  for (const Tri& f : boundary.faces) {
    Tri t;
    for (int i = 0; i < 3; ++i) {
      const auto it = local.emplace(f[i], static_cast<index_t>(p.size())).first;
      if (it->second == static_cast<index_t>(p.size())) p.push_back(points[f[i]]);
      t[i] = it->second;
    }
    tris.push_back(t);
  }
  SurfaceMesh surface;
  Status s = build_surface_mesh(p, tris, surface);
  if (!s) return Status::failure("object " + std::to_string(boundary.material) + ": " + s.message);
  Segmentation seg;
  s = segment_surface(surface, SegmentationParams(), seg);
  if (!s) return Status::failure("object " + std::to_string(boundary.material) + ": " + s.message);
  for (const Region& r : seg.regions) out.regions.push_back(r.surface);
  Vec3 lo = p[0], hi = p[0];
  for (const Vec3& q : p) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  out.scale = (hi - lo).norm();
  out.mean_edge = surface.mean_edge_length;
  return Status::success();
}

}  // namespace femorph
