// Points that lie on top of other points: duplicate nodes a mesh was not
// merged at (an unmerged seam between two parts of one body).
#pragma once

#include "common/types.h"

#include <cstddef>
#include <vector>

namespace femorph {

/// Number of points that have another point within `tolerance` (Euclidean
/// distance <= tolerance; tolerance 0: the same coordinates), by a spatial
/// hash of cell size `tolerance`: O(n log n), no pair loop.
/// Inputs:
///   points     #P positions (finite)
///   tolerance  >= 0, absolute
/// Returns how many of the points coincide with at least one other.
std::size_t count_coincident_points(const std::vector<Vec3>& points, double tolerance);

}  // namespace femorph
