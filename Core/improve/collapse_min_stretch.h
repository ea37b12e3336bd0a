// Quality an edge collapse would give, for choosing and guarding collapses in
// the degenerated and inverted element removal (thesis 2.6.2, Fig. 2.38, 2.39).
#pragma once

#include "common/types.h"

namespace femorph {

class TetMesh;

/// Minimum stretch (Eq. 1.1) of the tets around the merged vertex after
/// collapsing edge (keep, remove) with keep moved to `position`: the tets on
/// the edge vanish, the other tets of remove's ball take keep instead, the
/// other tets of keep's ball see it at `position`. These are exactly the tets
/// the collapse leaves changed. +inf when none would remain. Checks neither
/// the link condition nor the edge's existence (then remove's whole ball
/// counts as renamed).
double collapse_min_stretch(const TetMesh& mesh, index_t keep, index_t remove, const Vec3& position);

}  // namespace femorph
