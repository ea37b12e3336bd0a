// Parameterise once, reposition many (thesis 2.5.4: the positions are
// parameterised once, then each target value only repositions them): the
// state kept between target values of one deformation.
#include "deform/deform_internal.h"

#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace femorph {

Status DeformSession::prepare(const TetMesh& mesh, const DeformRegions& regions, const DeformOptions& options) {
  mesh_ = mesh;
  regions_ = regions;
  reach_ = -1;
  param_ = VertexParameterization();
  history_.clear();
  const RegionGraph graph = region_adjacency(mesh_, regions_.size());
  const Status s = classify_surface_regions(mesh_, regions_, graph, options, plan_);
  if (!s) return s;
  find_valid_range(mesh_, regions_, plan_);
  edge_ = mean_edge_length(mesh_);
  return Status::success();
}

Status DeformSession::reposition(double target, std::vector<Vec3>& points, std::vector<SurfacePrimitive>& surfaces,
                                 bool* reused) {
  const double tol = 1e-9 * std::max(1.0, std::abs(plan_.current));
  if (!(target >= plan_.valid_min - tol && target <= plan_.valid_max + tol)) {
    std::ostringstream os;
    os << "TargetValue " << target << " is outside the valid range [" << plan_.valid_min << ", " << plan_.valid_max
       << "] of this " << to_string(plan_.options.type) << " (now " << plan_.current << ").";
    return Status::failure(os.str());
  }
  const SurfaceUpdate update = update_region_surfaces(plan_, regions_, target);
  if (!update.error.empty()) return Status::failure("TargetValue " + std::to_string(target) + ": " + update.error + ".");
  // The reach of this change; the region is rebuilt only when it grows.
  const double move = largest_move(mesh_, plan_, update);
  const double reach = std::max(3 * edge_, 1.5 * move);
  const bool keep = reach_ >= reach;
  if (!keep) {
    std::vector<std::uint8_t> region;
    if (plan_.options.local_region) region = extract_deformable_region(mesh_, plan_, reach);
    history_.clear();
    const Status s = parameterize_vertices(mesh_, plan_, region, param_);
    if (!s) return s;
    reach_ = reach;
  }
  if (reused) *reused = keep;
  reposition_vertices(mesh_, regions_, param_, update, points, &history_);
  std::size_t inverted = 0;
  for (const index_t t : param_.moving_tets) {  // the others keep their volume
    const Tet& T = mesh_.tet(t);
    inverted += tet_signed_volume(points[T[0]], points[T[1]], points[T[2]], points[T[3]]) <= 0;
  }
  if (inverted) {
    std::ostringstream os;
    os << "the change to " << target << " inverts " << inverted
       << " tetrahedra; turn Improve on (it takes the change in steps and repairs them) or take a smaller change.";
    return Status::failure(os.str());
  }
  surfaces = update.surfaces;
  return Status::success();
}

}  // namespace femorph
