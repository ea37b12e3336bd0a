// Decomposition of hexahedra, wedges and pyramids into tetrahedra without
// new vertices (thesis 4.4, Fig. 4.5).
#pragma once

#include "common/types.h"
#include "hex/hex_decomposition_types.h"
#include "hex/mixed_cells.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femorph {

struct HexToTetParams {
  /// Conforming (default): every quad face is split along its diagonal
  /// through its smallest vertex id, on both sides, and each cell takes a
  /// triangulation realising its diagonals (for hexes the one whose worst
  /// tet has the best stretch, Eq. 1.1, among those of
  /// hex_decompositions_with_diagonals, the first of equals; the smallest
  /// vertex has three diagonals, so one always exists).
  /// A quad face whose two triangles along one diagonal are both faces of
  /// input tetrahedra (a non-conforming hex-dominant mesh, e.g. from Tet To
  /// Hex) keeps that diagonal instead, on as many such faces of the cell as
  /// a triangulation allows (the others are counted as non-conforming).
  /// Otherwise every hexahedron takes `type`/`mirrored` in its own node
  /// order (the thesis' C+ on structured grids), conforming or not; wedges
  /// and pyramids still follow the conforming rule.
  bool conforming = true;
  HexDecompositionType type = HexDecompositionType::C;
  bool mirrored = false;
};

struct HexToTetResult {
  std::vector<Tet> tets;               // positively oriented where the cell is
  std::vector<index_t> source_cell;    // input cell of each tet
  /// Per input hexahedron: the type used (as HexDecompositionType) and
  /// whether mirrored; -1 for other cells. In conforming mode the type is
  /// the Fig. 4.5 class of the chosen triangulation (invariant under the
  /// cube's symmetries) and mirrored is 0: "+" and "-" only mean something
  /// in a fixed node order (C- is C+ turned by 90 degrees).
  std::vector<std::int8_t> hex_type;
  std::vector<std::int8_t> hex_mirrored;
  std::size_t inverted_cells = 0;      // cells giving a tet of volume <= 0
  std::vector<index_t> inverted;       // their ids, ascending
  /// Per tet: 1 when its volume is <= 0 (exact orientation sign), else 0.
  std::vector<std::uint8_t> tet_inverted;
  /// Quad faces whose two sides are split along different diagonals: two
  /// cells of the input sharing the quad, or a cell and the two input tets
  /// on it. 0 in conforming mode unless input tets force a diagonal that a
  /// neighbouring cell cannot realise.
  std::size_t nonconforming_faces = 0;
  /// Quad faces that follow the diagonal of the input tets on them.
  std::size_t quads_following_tets = 0;
};

/// Splits every cell of `cells` into tetrahedra over the same points (thesis
/// 4.4): hexahedra into 5 or 6 (Fig. 4.5), wedges into 3, pyramids into 2,
/// tetrahedra copied. Tets come out cell by cell in input order.
/// Fails with a message (and an empty result) on a node id out of range, a
/// cell with a repeated node, two cells over the same nodes, a non-finite
/// coordinate, or inconsistent offsets. Inverted output tets are reported, not refused.
Status decompose_to_tetrahedra(const std::vector<Vec3>& points, const MixedCells& cells,
                               const HexToTetParams& params, HexToTetResult& result);

}  // namespace femorph
