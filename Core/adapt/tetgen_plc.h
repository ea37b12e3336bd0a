// TetGen behind one call, for the Adapt steps that mesh a piecewise linear
// complex (mesh_space_around, tetrahedralize_hole of thesis 3.5.5): the
// tetgenio set-up, the error handling and the output orientation live here
// once, and tetgen.h stays inside tetgen_plc.cpp.
#pragma once

#include "common/types.h"

#include <array>
#include <vector>

namespace femorph {
namespace internal {

/// Tetrahedralizes the PLC of `points` and the triangles `facets` (ids into
/// points) with TetGen's `switches` (e.g. "pYq1.4Q"); `holes` are points
/// inside regions to leave empty. On success `out_points` starts with
/// `points` in order (checked), then TetGen's Steiner points, and `out_tets`
/// are positively oriented (exact predicate). Fails, never throws nor exits,
/// when TetGen stops (its error code in the message) or returns a flat tet.
/// TetGen runs in a forked process (POSIX): Debian's TetGen 1.5.0 frees its
/// memory twice on an error, which would crash the caller. Its standard
/// output is captured: without Q in the switches, a failure's message
/// quotes why TetGen stopped.
Status tetgen_plc(const std::vector<Vec3>& points, const std::vector<std::array<index_t, 3>>& facets,
                  const std::vector<Vec3>& holes, const char* switches, std::vector<Vec3>& out_points,
                  std::vector<Tet>& out_tets);

}  // namespace internal
}  // namespace femorph
