// Flips 2-3, 3-2 and 4-4 of the tetrahedron improvement (thesis 2.6.5.4,
// Fig. 2.46).
#pragma once

#include "common/types.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femorph {

class TetMesh;

struct FlipImproveOptions {
  /// Tets with stretch (Eq. 1.1) below this enter the work queue.
  double quality_threshold = 0.4;
  /// The Delaunay conditions of 2.6.5.4: (1) some old tet is not locally
  /// Delaunay, (2) every new tet is Delaunay with respect to the vertices of
  /// the flipped cavity and of its face neighbours. Condition (3), a higher
  /// minimum stretch, always applies. Off by default: with the boundary held
  /// fixed, (1)-(2) block most useful flips (fandisk with its inner vertices
  /// moved by 40% keeps a far lower minimum stretch with them).
  bool delaunay_conditions = false;
  /// Upper bound on queue pops (an iteration limit), 0 = 20 x #tets.
  std::size_t max_visits = 0;
  /// A flip must raise the minimum stretch by more than this.
  double min_gain = 1e-9;
  /// Per vertex slot (as OdtSmoothOptions::vertex_mask): a flip is allowed
  /// only when each tet it removes or creates has a vertex with mask 1, so
  /// the tets with no masked vertex stay as they are. Empty: everywhere.
  std::vector<std::uint8_t> vertex_mask;
};

struct FlipImproveReport {
  std::size_t flips_23 = 0, flips_32 = 0, flips_44 = 0;
  std::size_t visits = 0;      // queue pops
  bool exhausted = false;      // stopped by max_visits, not by an empty queue
  std::size_t total() const { return flips_23 + flips_32 + flips_44; }
};

/// Work queue over the tets below the threshold (FIFO, ids ascending at the
/// start: deterministic). For a popped tet, every flip of its faces (2-3) and
/// edges (3-2 on valence 3, 4-4 on valence 4, both diagonals) is evaluated;
/// the one giving the highest minimum stretch of the new tets is applied when
/// it beats the minimum of the old tets (and meets the Delaunay conditions
/// when asked). New tets below the threshold are queued again. Ends when the
/// queue is empty (no improving flip left) or after max_visits pops.
/// TetMesh validates every flip (exact orientation, no duplicate entity).
/// The queue is popped in batches of 64 whose flips are evaluated in
/// parallel and applied in queue order (a tet whose vertices an earlier flip
/// of the batch used is queued again): the result does not depend on the
/// number of threads.
FlipImproveReport improve_tets_by_flips(TetMesh& mesh, const FlipImproveOptions& options = {});

}  // namespace femorph
