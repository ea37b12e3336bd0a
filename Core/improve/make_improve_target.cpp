// The density field and acceptable geometric error FEMorph Improve aims at
// (thesis 2.6.3, Eq. 2.32-2.33; 2.6.4).
#include "improve/control_shape_accuracy.h"
#include "improve/improve_target.h"
#include "mesh/tet_mesh.h"

#include <algorithm>
#include <limits>

namespace femorph {
namespace {

Tet sorted(Tet t) {
  std::sort(t.begin(), t.end());
  return t;
}

/// The same points and the same tets in the same order (a tet's vertices in
/// any order: the mesh may have flipped the input's orientation).
bool same_connectivity(const std::vector<Vec3>& points, const std::vector<Tet>& tets, const ReferenceMesh& reference) {
  if (reference.points.size() != points.size() || reference.tets.size() != tets.size()) return false;
  for (std::size_t t = 0; t < tets.size(); ++t)
    if (sorted(tets[t]) != sorted(reference.tets[t])) return false;
  return true;
}

}  // namespace

ImproveTarget make_improve_target(const TetMesh& mesh, const BoundaryGeometry* geometry,
                                  const ReferenceMesh* reference, const ImproveTargetOptions& options) {
  ImproveTarget target;
  const bool has_reference = reference && !reference->tets.empty();
  const std::vector<Vec3>& points = mesh.points();
  const std::vector<Tet> tets = live_tet_list(mesh);
  // Improve looks the field up per cell (rho_GC), not trilinearly.
  constexpr bool with_trilinear = false;

  if (options.density) {
    const std::vector<Vec3>& from_points = has_reference ? reference->points : points;
    const std::vector<Tet>& from_tets = has_reference ? reference->tets : tets;
    double mean_length = 0;
    const std::vector<double> densities = vertex_density(from_points, from_tets, &mean_length);
    const double cell = options.grid_cell_size > 0 ? options.grid_cell_size : 0.5 * mean_length;
    // Eq. 2.33: with the input's connectivity the densities travel with the
    // material; otherwise the reference's field is used in space.
    const bool on_input = !has_reference || same_connectivity(points, tets, *reference);
    const bool built = on_input ? target.density.build(points, tets, densities, cell, options.max_grid_points, with_trilinear)
                                : target.density.build(from_points, from_tets, densities, cell,
                                                       options.max_grid_points, with_trilinear);
    if (!built && has_reference)
      target.warnings.push_back(
          "no density field could be made from the Reference (grid too fine or no tetrahedra); density "
          "control is off.");
  }

  if (!geometry) return target;
  if (has_reference) {
    if (!reference->region_types.empty() && reference->region_types.size() == geometry->regions.size() &&
        reference->face_regions.size() == reference->tets.size()) {
      // From the reference's boundary faces: no TetMesh of it is needed.
      target.acceptable_error = region_geometric_error(reference->points, reference->tets, reference->face_regions,
                                                       reference->geometry);
      // A region whose type changed (e.g. a torus stretched into a freeform
      // face) has no target.
      for (std::size_t r = 0; r < target.acceptable_error.size(); ++r)
        if (reference->region_types[r] != geometry->regions[r].type)
          target.acceptable_error[r] = std::numeric_limits<double>::quiet_NaN();
    } else {
      target.warnings.push_back(
          "the Reference has no segmentation arrays matching the input's regions; the input's own geometric "
          "error is kept.");
    }
  }
  if (target.acceptable_error.empty()) target.acceptable_error = region_geometric_error(mesh, *geometry);
  return target;
}

}  // namespace femorph
