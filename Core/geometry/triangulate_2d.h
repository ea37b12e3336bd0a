// Constrained Delaunay triangulation in the plane. Adapt's contact regions
// (thesis 3.5.4) are re-triangulated in the 2D parameter space of their
// surface (3.4.2: development planes, angles), where the boundary lines of
// the overlap and the edges kept from the meshes are constraints.
#pragma once

#include "common/types.h"

#include <vector>

namespace femorph {

using Vec2 = Eigen::Vector2d;
using Triangle = std::array<index_t, 3>;
using Segment2 = std::array<index_t, 2>;

/// Constrained Delaunay triangulation of `points` (all used) in which every
/// segment is a union of edges: a segment through an input point is split
/// there. `triangles` receives the counter-clockwise triangles covering the
/// convex hull; with `component`, each triangle's region: triangles are in
/// the same region when joined across edges that are no segment's. Fails,
/// naming them, on duplicate points, crossing segments, segments with a bad
/// index, and fewer than three points not on one line. Exact predicates.
Status constrained_delaunay_2d(const std::vector<Vec2>& points, const std::vector<Segment2>& segments,
                               std::vector<Triangle>& triangles, std::vector<index_t>* component = nullptr);

}  // namespace femorph
