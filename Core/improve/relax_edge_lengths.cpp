// Edge length relaxation toward the target density; see relax_edge_lengths.h.
#include "improve/relax_edge_lengths.h"

#include "improve/mesh_density.h"

namespace femorph {

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

}  // namespace femorph
