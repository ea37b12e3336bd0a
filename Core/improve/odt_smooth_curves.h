// ODT smoothing of the boundary edges, phase (1) of Phased ODT smoothing
// (thesis 2.6.5.2, Eq. 2.34, Fig. 2.42).
#pragma once

#include "improve/odt_smooth_surface.h"

namespace femorph {

/// Moves each vertex whose constraint is VertexConstraint::Curve along its
/// curve by Eq. 2.34 over its two curve edges (the boundary edges between
/// different regions, TetMesh::is_curve_edge):
///   line (a Line curve, or two planes without a known curve): CPT smoothing,
///        the mean of the two edge midpoints;
///   circle / circular arc: the same in the central angle about the curve's
///        centre and normal (Fig. 2.42), angles taken relative to the vertex
///        so wrap-around does not matter;
///   other curves (two fitted surfaces): the mean of the edge midpoints,
///        projected onto both surfaces (alternating projections).
/// Every position is projected onto the constraint (project_to_constraint).
/// Step alpha = 1, halved while the move would invert a tet (exact) or, with
/// the quality guard, lower the ball's minimum stretch. No flips (thesis).
/// Corner and fixed vertices never move. Id order: deterministic.
OdtSmoothReport odt_smooth_curves(TetMesh& mesh, const BoundaryGeometry& geometry,
                                  const BoundarySmoothOptions& options = {});

}  // namespace femorph
