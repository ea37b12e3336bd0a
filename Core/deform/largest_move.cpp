// How far a change moves the boundary: the reach of the deformable region
// (2.5.3) and the scale of the smallest one.
#include "deform/deform_internal.h"

#include "improve/mesh_density.h"
#include "mesh/tet_mesh.h"

#include <algorithm>

namespace femorph {

double largest_move(const TetMesh& mesh, const DeformPlan& plan, const SurfaceUpdate& update) {
  double d = 0;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f) {
      const index_t r = mesh.face_region(t, f);
      if (r < 0 || r >= static_cast<index_t>(plan.roles.size())) continue;
      if (plan.roles[r] != RegionRole::Control && plan.roles[r] != RegionRole::Following) continue;
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = mesh.point(mesh.tet(t)[kTetFace[f][k]]);
        d = std::max(d, (update.map(r, p) - p).norm());
      }
    }
  }
  return d;
}

double mean_edge_length(const TetMesh& mesh) { return mean_edge_length(mesh.points(), live_tet_list(mesh)); }

}  // namespace femorph
