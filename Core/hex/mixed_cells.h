// A mesh of tetrahedra, pyramids, wedges and hexahedra in VTK's layout
// (node orders of VTK_TETRA, VTK_PYRAMID, VTK_WEDGE, VTK_HEXAHEDRON), for the
// conversions between tet and hex meshes (thesis chapter 4).
#pragma once

#include "common/types.h"
#include "quality/tet_quality.h"

#include <array>
#include <vector>

namespace femorph {

struct MixedCells {
  std::vector<CellKind> kinds;        // one per cell
  std::vector<index_t> offsets{ 0 };  // #cells + 1: nodes of cell c are
  std::vector<index_t> connectivity;  //   connectivity[offsets[c] .. offsets[c + 1])

  index_t size() const { return static_cast<index_t>(kinds.size()); }
  index_t node_count(index_t c) const { return offsets[c + 1] - offsets[c]; }
  const index_t* nodes(index_t c) const { return connectivity.data() + offsets[c]; }
  void add(CellKind kind, const index_t* nodes) {
    kinds.push_back(kind);
    connectivity.insert(connectivity.end(), nodes, nodes + cell_node_count(kind));
    offsets.push_back(static_cast<index_t>(connectivity.size()));
  }
};

/// The two lowest ids of cells over the same set of nodes (a cell written
/// twice), the smaller first; {-1, -1} when every cell has its own nodes.
std::array<index_t, 2> find_duplicate_cells(const MixedCells& cells);

}  // namespace femorph
