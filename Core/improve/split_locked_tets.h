// Beyond the thesis: a tet whose four vertices lie on the boundary (at a
// sharp edge, in a thin wall) has no inner vertex ODT could move. Splitting
// one of its interior edges (an edge through the inside between two boundary
// vertices) gives it one; optimize_worst_vertices() then places it.
#pragma once

#include "common/types.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femorph {

class TetMesh;

struct LockedTetOptions {
  /// Tets with stretch (Eq. 1.1) below this and no inner vertex are split.
  double threshold = 0.3;
  /// Per vertex slot: only edges whose two ends are flagged. Empty: all.
  std::vector<std::uint8_t> vertex_mask;
  /// Off: every tet below the threshold, not only those without an inner
  /// vertex (the last resort for tets that smoothing, vertex placement and
  /// flips left below it).
  bool only_locked = true;
};

struct LockedTetStats {
  std::size_t locked = 0;  ///< tets below the threshold with no inner vertex (all with only_locked off)
  std::size_t splits = 0;  ///< interior edges split (and kept)
};

/// For each tet below the threshold whose vertices are all on the boundary,
/// lowest stretch first: its interior edges, longest first; the first whose
/// split at the midpoint, with the new vertex then moved by compass search
/// to maximise the minimum stretch of its ball, beats the worst tet around
/// the edge before is split, and the new vertex placed there. Each tet is
/// evaluated before any change (read only), in batches in parallel; a tet
/// whose evaluation an earlier split of its batch made stale goes into the
/// next batch. Deterministic, for any number of threads.
LockedTetStats split_locked_tets(TetMesh& mesh, const LockedTetOptions& options = {});

}  // namespace femorph
