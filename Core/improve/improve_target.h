// What FEMorph Improve aims at (thesis 2.6.3, 2.6.4): the target mesh
// density field and the acceptable geometric error per region, from the mesh
// before the deformation (the reference) or, without one, from the mesh
// itself.
#pragma once

#include "common/types.h"
#include "geometry/surface_primitive.h"
#include "improve/boundary_geometry.h"
#include "improve/mesh_density.h"
#include "improve/phased_odt.h"

#include <cstddef>
#include <string>
#include <vector>

namespace femorph {

class TetMesh;

/// The mesh before the deformation.
struct ReferenceMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  /// Its segmentation, when it has one: per tet the region of the face
  /// opposite local vertex i (-1 interior), in the numbering of `tets`, and
  /// per region its type; both empty otherwise.
  std::vector<Tet> face_regions;
  std::vector<SurfaceType> region_types;
  BoundaryGeometry geometry;
};

/// Fails with a message naming the first problem when `reference` is no
/// mesh to take a target from: a point id out of range, a tetrahedron with a
/// repeated point or zero volume, tetrahedra oriented both ways.
Status check_reference_mesh(const ReferenceMesh& reference);

struct ImproveTargetOptions {
  /// Build the density field (off for Poor Elements Only, which needs none).
  bool density = true;
  /// Density grid spacing; <= 0: half the mean edge length of the mesh the
  /// densities come from (thesis 2.6.3).
  double grid_cell_size = 0;
  /// A finer grid than this many points is refused (density control off).
  std::size_t max_grid_points = std::size_t(1) << 27;
};

struct ImproveTarget {
  /// Eq. 2.33; empty when no field could be made.
  DensityGrid density;
  /// Acceptable geometric error per region id (NaN: none).
  std::vector<double> acceptable_error;
  /// What the caller should tell the user (e.g. no density field).
  std::vector<std::string> warnings;

  /// The target as phased_odt takes it (pointing into this object).
  PhasedOdtTarget view() const {
    PhasedOdtTarget t;
    t.density = density.empty() ? nullptr : &density;
    t.acceptable_error = acceptable_error;
    return t;
  }
};

/// The target of Phased ODT for `mesh` (the deformed mesh, as built from the
/// input: vertex slot i = input point i, tet slot t = input cell t).
/// `geometry`: the input's segmentation (null: none, so no accuracy target).
/// `reference` (may be null or without tets): the mesh before the
/// deformation.
///  - Density (Eq. 2.32, 2.33): the vertex densities of the reference. With
///    the input's connectivity they travel with the material (the grid is
///    built over the deformed mesh); otherwise the reference's own field is
///    taken in space. Without a reference, the input's own density.
///  - Acceptable error (2.6.4): the reference's largest geometric error per
///    region, when its segmentation has as many regions as `geometry`
///    (NaN where the region's type changed); otherwise the input's own.
ImproveTarget make_improve_target(const TetMesh& mesh, const BoundaryGeometry* geometry,
                                  const ReferenceMesh* reference, const ImproveTargetOptions& options = {});

}  // namespace femorph
