// Edge length relaxation toward the target density; see relax_edge_lengths.h.
#include "improve/relax_edge_lengths.h"

#include "improve/mesh_density.h"
#include "improve/odt_smooth_surface.h"
#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cstdint>

namespace femorph {

bool spring_rest(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v,
                 const std::function<double(const Vec3&)>& density, std::vector<index_t>& neighbours, Vec3* step,
                 double* mean_length) {
  // Each neighbour once, in the order met (the sum below adds in that
  // order): stamped per vertex slot, not searched for in the list (a
  // search per neighbour is quadratic in the ball).
  thread_local TetMesh::VertexStamps seen;
  const std::uint32_t stamp = seen.next(static_cast<std::size_t>(mesh.vertex_slots()));
  seen.stamp[static_cast<std::size_t>(v)] = stamp;
  neighbours.clear();
  for (const index_t t : ball)
    for (const index_t w : mesh.tet(t))
      if (seen.stamp[static_cast<std::size_t>(w)] != stamp) {
        seen.stamp[static_cast<std::size_t>(w)] = stamp;
        neighbours.push_back(w);
      }
  const Vec3 x = mesh.point(v);
  Vec3 sum = Vec3::Zero();
  double sum_len = 0;
  int n = 0;
  for (const index_t w : neighbours) {
    const Vec3& q = mesh.point(w);
    const double length = (x - q).norm(), rho = density(0.5 * (x + q));
    if (!(length > 0) || !(rho > 0)) continue;
    sum += q + (x - q) / (rho * length);
    sum_len += length;
    ++n;
  }
  if (n == 0) return false;
  *step = sum / n - x;
  if (mean_length) *mean_length = sum_len / n;
  return true;
}

OdtSmoothReport relax_edge_lengths(TetMesh& mesh, const DensityGrid& grid, const RelaxEdgeLengthsOptions& options) {
  if (grid.empty()) return {};
  OdtSmoothOptions smooth;
  smooth.iterations = options.iterations;
  smooth.vertex_mask = options.vertex_mask;
  smooth.edge_density = [&grid](const Vec3& p) { return grid.density_at(p, DensityLookup::Cell); };
  smooth.guard_drop = options.guard_drop;
  smooth.guard_keep = options.guard_keep;
  smooth.max_halvings = options.max_halvings;
  return odt_smooth_volume(mesh, smooth);
}

OdtSmoothReport relax_surface_edge_lengths(TetMesh& mesh, const BoundaryGeometry& geometry, const DensityGrid& grid,
                                           const RelaxEdgeLengthsOptions& options) {
  if (grid.empty()) return {};
  BoundarySmoothOptions smooth;
  smooth.iterations = options.iterations;
  smooth.vertex_mask = options.vertex_mask;
  smooth.quality_floor = options.quality_floor;
  smooth.acceptable_error = options.acceptable_error;
  smooth.edge_density = [&grid](const Vec3& p) { return grid.density_at(p, DensityLookup::Cell); };
  smooth.guard_drop = options.guard_drop;
  smooth.guard_keep = options.guard_keep;
  smooth.max_halvings = options.max_halvings;
  return odt_smooth_surface(mesh, geometry, smooth);
}

}  // namespace femorph
