// Boundary curves of a changed mesh: the chains of its curve edges (boundary
// edges between two regions), matched to the curves of the mesh it came from,
// so the segmentation's curve vertex lists stay right after an operation
// that adds, removes or renumbers vertices (Improve, Deform, Adapt).
#pragma once

#include "common/types.h"
#include "mesh/tet_mesh.h"

#include <vector>

namespace femorph {

/// Inputs:
///   mesh          the new mesh (compacted: face_regions per tet face, vertex_map)
///   old_curves    vertex lists of the old curves, in old vertex slots (ordered;
///                 a loop does not repeat its first vertex)
///   old_regions   the two regions of each old curve
/// Returns, per old curve, its ordered vertex list in the new mesh's ids: the
/// chain of curve edges between the same two regions (from corner to corner,
/// or a loop) holding most of the curve's surviving vertices, oriented like
/// the old list. A curve with no such chain gets an empty list.
std::vector<std::vector<index_t>> trace_boundary_curves(const CompactMesh& mesh,
                                                        const std::vector<std::vector<index_t>>& old_curves,
                                                        const std::vector<std::array<index_t, 2>>& old_regions);

}  // namespace femorph
