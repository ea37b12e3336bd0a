// Fallback of the inverted element removal (thesis 2.6.2) for tangles the
// half-edge collapses of Fig. 2.39 cannot undo: a vertex is moved to the mean
// of its neighbours, inside its face plane for a surface vertex. Not in the
// thesis.
#pragma once

#include "common/types.h"
#include "improve/remove_degenerate_elements.h"  // ProjectVertexFn

namespace femorph {

class TetMesh;

/// Moves vertex v to the mean of its neighbours (inner vertex), or of the
/// other vertices of its boundary faces (surface vertex), or part of the way
/// there (fractions 1, 1/2, 1/4), accepting the first position at which every
/// tet of its ball is positive (TetMesh::move_vertex). A surface vertex moves
/// only when its boundary faces are coplanar (the target is projected onto
/// their plane, so the boundary keeps its shape exactly) or, on a curved
/// region, when `project` is given (the target is projected by it). Curve and
/// corner vertices never move. Returns true when v moved.
bool untangle_vertex(TetMesh& mesh, index_t v, const ProjectVertexFn& project = {});

}  // namespace femorph
