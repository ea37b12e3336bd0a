// Edge length relaxation toward the target density (beyond the thesis):
// after ODT has shaped the tets, each inner vertex moves toward the rest
// position of springs along its edges, each as long as 1 / rho_GC at the
// edge's midpoint, so that the edge lengths follow the field (Eq. 2.35).
#pragma once

#include "improve/odt_smooth_volume.h"

#include <cstdint>
#include <vector>

namespace femorph {

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
};

/// Moves the free inner vertices toward their springs' rest position
/// (OdtSmoothOptions::edge_density with rho_GC of `grid`), with the step
/// halving and the quality guard of odt_smooth_volume: no tet inverts and no
/// ball's minimum stretch drops. Deterministic, independent of the number
/// of threads.
OdtSmoothReport relax_edge_lengths(TetMesh& mesh, const DensityGrid& grid, const RelaxEdgeLengthsOptions& options);

}  // namespace femorph
