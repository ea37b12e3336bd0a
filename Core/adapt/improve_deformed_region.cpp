// Mesh quality improvement of thesis 3.6: Improve's modified ODT loop
// (removal of inverted and degenerated elements, density control by edge
// collapse and split, ODT smoothing, flips) on the deformed region, its
// boundary (the object's surface, the domain's boundary, the tets around the
// region) fixed. The target density is the input mesh's, a field fixed in
// space (3.6: "keeping the edge length of the original input mesh"), so the
// vertex count stays near the input's over hundreds of steps.
#include "adapt/adapt.h"

#include "improve/boundary_geometry.h"
#include "improve/mesh_density.h"
#include "improve/phased_odt.h"

#include <limits>
#include <sstream>

namespace femorph {

Status improve_deformed_region(RegionMesh& region, const DensityGrid* density, double density_scale,
                               double quality_floor) {
  static const BoundaryGeometry kNoGeometry;
  PhasedOdtTarget target;
  target.density = density;
  PhasedOdtOptions options;
  options.fix_boundary = true;
  options.split_inner_edges = true;
  options.smooth_curves = false;
  options.smooth_surfaces = false;
  options.accuracy_control = false;
  options.move_unfitted_regions = false;
  options.quality_floor = quality_floor;
  // The density scaled by density_scale: a scaled length L rho k passes a
  // threshold b when L rho passes b / k. The relaxation toward 1 / rho
  // would undo the scale.
  options.split_threshold /= density_scale;
  options.collapse_threshold /= density_scale;
  options.relax_edge_lengths = false;
  options.odt_iterations = 1;
  // Vertex ids are mapped back to the space mesh: no renumbering.
  options.sort_min_tets = std::numeric_limits<std::size_t>::max();
  const PhasedOdtStats stats = phased_odt(region.mesh, kNoGeometry, target, options);
  if (!stats.remaining_inverted.empty()) {
    std::ostringstream os;
    os << stats.remaining_inverted.size() << " tetrahedra of the deformed region stay inverted after its improvement";
    return Status::failure(os.str());
  }
  return Status::success();
}

}  // namespace femorph
