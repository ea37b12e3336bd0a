// Phase (3) of Phased ODT smoothing, the tetrahedron improvement (thesis
// 2.6.5.4; the loop of Fig. 2.34 restricted to ODT smoothing and flips).
#pragma once

#include "improve/improve_tets_by_flips.h"
#include "improve/odt_smooth_volume.h"

namespace femorph {

class TetMesh;

struct ImproveVolumeOptions {
  /// Rounds of (ODT smoothing, then flips).
  int rounds = 4;
  /// Smoothing of each round; its vertex_mask is also given to the flips
  /// (FlipImproveOptions::vertex_mask is overwritten by it).
  OdtSmoothOptions smooth;
  FlipImproveOptions flips;
  /// Stop early when a round neither flipped nor moved a vertex farther than
  /// smooth.tolerance.
  bool stop_when_converged = true;
};

struct ImproveVolumeStats {
  double min_stretch_before = 0, mean_stretch_before = 0;
  double min_stretch_after = 0, mean_stretch_after = 0;
  int rounds = 0;
  std::size_t moved = 0, refused = 0;
  std::size_t flips_23 = 0, flips_32 = 0, flips_44 = 0;
  double seconds = 0;
};

/// Minimum and mean stretch (Eq. 1.1) over the live tets.
void live_stretch_range(const TetMesh& mesh, double* min_stretch, double* mean_stretch);

/// Alternates odt_smooth_volume and improve_tets_by_flips for a few rounds.
/// Boundary vertices never move; inner ones only where the mask allows.
ImproveVolumeStats improve_volume(TetMesh& mesh, const ImproveVolumeOptions& options = {});

}  // namespace femorph
