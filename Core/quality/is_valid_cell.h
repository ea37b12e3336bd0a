// FEMorph's one definition of a valid linear cell, shared by Mesh Quality
// (its Invalid flag) and Hex To Tet (a valid cell never gives an inverted
// tet, whatever diagonals its neighbours impose on its quads).
#pragma once

#include "common/types.h"
#include "quality/tet_quality.h"

namespace femorph {

/// Whether a cell is valid: every tetrahedron on four of its nodes that are
/// not coplanar in the reference cell (hex_decomposition_types.h) has
/// positive volume, by the exact orientation sign (orient3d_sign).
///   Tetra       the tet itself (1 tet)
///   Pyramid     4 tets (the 5 node sets but the base)
///   Wedge       12 tets (the 15 node sets but the 3 quads)
///   Hexahedron  58 tets (the 70 node sets but the 6 faces and 6 diagonal
///               planes)
/// Every tet of every split into tetrahedra without new points (thesis 4.4:
/// Fig. 4.5's types in any node order, the wedge's and the pyramid's splits)
/// is among them, so a valid cell splits into positive tets whatever the
/// diagonals of its quads; an invalid one has a flat or inverted tet over
/// four of its nodes, which a split may use (Hex To Tet then reports the cell
/// inverted, or not, depending on the diagonals it takes). This is stricter
/// than Eq. 4.2's corners: a hexahedron
/// whose top face is turned by 90 degrees has scaled Jacobian sqrt(2)/2 at
/// every corner (as VTK's Verdict says) but is invalid (its side quads are
/// twisted so far that splitting them along a diagonal folds the cell).
/// Inputs:
///   kind    cell kind
///   points  cell_node_count(kind) points in VTK order
/// Exact at any scale of the coordinates (orient3d_sign).
bool is_valid_cell(CellKind kind, const Vec3* points);

}  // namespace femorph
