// Edge length relaxation toward the target density (beyond the thesis):
// after ODT has shaped the tets, each inner vertex moves toward the rest
// position of springs along its edges, each as long as 1 / rho_GC at the
// edge's midpoint, so that the edge lengths follow the field (Eq. 2.35).
#pragma once

#include "improve/odt_smooth_volume.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace femorph {

struct BoundaryGeometry;
class DensityGrid;
class TetMesh;

struct RelaxEdgeLengthsOptions {
  /// Gauss-Seidel sweeps (colour by colour, as odt_smooth_volume).
  int iterations = 2;
  /// Per vertex slot: only vertices with mask 1 move. Empty: every inner vertex.
  std::vector<std::uint8_t> vertex_mask;
  /// The guard (OdtSmoothOptions::guard_drop, guard_keep) and the step
  /// halvings.
  double guard_drop = 0.1;
  double guard_keep = 0.35;
  int max_halvings = 3;
  /// relax_surface_edge_lengths only: no tet of a ball at or above this
  /// stretch falls below it (BoundarySmoothOptions::quality_floor), and a
  /// move keeps the chords of curved regions within these acceptable errors
  /// (2.6.4; null: not checked).
  double quality_floor = 0.3;
  const std::vector<double>* acceptable_error = nullptr;
};

/// OdtSmoothOptions::edge_density: the step from v to the rest position of
/// the springs along its edges (each neighbour of v's ball once), and the
/// edges' mean length when asked; false when no edge has a length and a
/// density. neighbours: scratch.
bool spring_rest(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v,
                 const std::function<double(const Vec3&)>& density, std::vector<index_t>& neighbours, Vec3* step,
                 double* mean_length = nullptr);

/// Moves the free inner vertices toward their springs' rest position
/// (OdtSmoothOptions::edge_density with rho_GC of `grid`), with the step
/// halving and the quality guard of odt_smooth_volume: no tet inverts and no
/// ball's minimum stretch drops. Deterministic, independent of the number
/// of threads.
OdtSmoothReport relax_edge_lengths(TetMesh& mesh, const DensityGrid& grid, const RelaxEdgeLengthsOptions& options);

/// The same for the surface vertices (class Surface, one fitted or kept
/// region): each moves toward its springs' rest position along the surface,
/// the step taken in the region's parameter plane and the point projected
/// back (odt_smooth_surface with BoundarySmoothOptions::edge_density), so
/// it stays on the fitted surface. Curve and corner vertices do not move.
/// The inner vertices' relaxation cannot lengthen the surface edges, which
/// Eq. 2.35 finds the furthest from the field.
OdtSmoothReport relax_surface_edge_lengths(TetMesh& mesh, const BoundaryGeometry& geometry, const DensityGrid& grid,
                                           const RelaxEdgeLengthsOptions& options);

}  // namespace femorph
