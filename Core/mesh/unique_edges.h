// The distinct edges of a tet mesh, sorted, in O(#tets): bucketed by their
// smaller vertex (a counting sort), each bucket sorted on its own: faster
// than sorting the 6 #T edge keys globally.
#pragma once

#include "common/types.h"

#include <utility>
#include <vector>

namespace femorph {

class TetMesh;

using Edge = std::pair<index_t, index_t>;

/// Distinct edges (a < b) of `tets` over vertices 0 .. num_vertices - 1,
/// sorted by (a, b). Tets whose first id is negative (tombstones) are skipped.
std::vector<Edge> unique_edges(const std::vector<Tet>& tets, index_t num_vertices);

/// The same for the live tets of a mesh; with `mask` (one flag per vertex
/// slot; an empty mask flags every vertex, slots past its end are not
/// flagged) only edges whose two ends are flagged.
std::vector<Edge> unique_edges(const TetMesh& mesh, const std::vector<char>* mask = nullptr);

}  // namespace femorph
