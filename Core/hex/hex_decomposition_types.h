// The decompositions of a hexahedron, a wedge and a pyramid into tetrahedra
// without new vertices (thesis 4.4, Fig. 4.5), as tables over the cell's
// local node ids in VTK's node order. Shared by Hex To Tet (which applies
// them) and Tet To Hex (whose RF-graph search matches them, 4.5.2).
//
// Reference cells (VTK node orders, positive orientation):
//   hexahedron 0 (0,0,0) 1 (1,0,0) 2 (1,1,0) 3 (0,1,0)
//              4 (0,0,1) 5 (1,0,1) 6 (1,1,1) 7 (0,1,1)
//   wedge      0 (0,0,0) 1 (0,1,0) 2 (1,0,0) 3 (0,0,1) 4 (0,1,1) 5 (1,0,1)
//   pyramid    0 (0,0,0) 1 (1,0,0) 2 (1,1,0) 3 (0,1,0) 4 (0.5,0.5,1)
// Thesis node k of Fig. 4.5 is VTK node k - 1 (bottom 1-4, top 5-8, 5 above 1).
#pragma once

#include "common/types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace femorph {

/// A tet over a cell's local node ids, positively oriented on the reference cell.
using LocalTet = std::array<std::int8_t, 4>;

/// Thesis Fig. 4.5: A (5 tets: four corners and the centre), B (A after a
/// flip 2-3 of the centre and a corner), C (6 tets around a main diagonal,
/// the thesis' default), D (C with one quad's diagonal flipped), E (C with
/// two opposite quads flipped), F (B with one quad flipped).
enum class HexDecompositionType : std::uint8_t { A = 0, B, C, D, E, F };
constexpr int kHexDecompositionTypes = 6;
const char* to_string(HexDecompositionType type);

/// One triangulation of the hexahedron.
struct HexDecomposition {
  HexDecompositionType type = HexDecompositionType::C;
  bool mirrored = false;       // the "-" variant of Fig. 4.5
  std::vector<LocalTet> tets;  // 5 or 6
  /// Diagonal of each quad face (kHexFaces order), as the bit of
  /// hex_face_diagonal_bit: 0 the diagonal through the face's node 0 and 2,
  /// 1 through nodes 1 and 3.
  std::uint8_t diagonals = 0;
};

/// The six quad faces of a hexahedron (VTK's face order), nodes ordered
/// with the outward normal by the right-hand rule.
extern const std::array<std::array<std::int8_t, 4>, 6> kHexFaces;
/// The three quad faces of a wedge, outward.
extern const std::array<std::array<std::int8_t, 4>, 3> kWedgeQuadFaces;

/// Fig. 4.5 type `type`, "+" (mirrored = false) or "-" (its mirror image in
/// the plane x = 1/2 of the reference hexahedron: nodes 0<->1, 2<->3, 4<->5,
/// 6<->7), with its tets and face diagonals.
const HexDecomposition& hex_decomposition(HexDecompositionType type, bool mirrored);

/// Every triangulation of the hexahedron without new vertices: the twelve
/// of hex_decomposition under the 48 symmetries of the cube, duplicates
/// removed (74 of them). Each keeps the type it came from.
const std::vector<HexDecomposition>& all_hex_decompositions();

/// The triangulations realising the face diagonals `diagonals` (bits as in
/// HexDecomposition::diagonals); empty for the 18 of the 64 patterns no
/// triangulation without new vertices realises (46 are realised; every
/// pattern in which some vertex carries the diagonals of its three faces is).
std::vector<const HexDecomposition*> hex_decompositions_with_diagonals(std::uint8_t diagonals);

/// The wedge split into 3 tets: the diagonals of its three quads
/// (kWedgeQuadFaces order, bit as for hexahedra). False (and no tets) for
/// the two cyclic patterns that need a new vertex.
bool wedge_decomposition(std::uint8_t diagonals, std::array<LocalTet, 3>& tets);

/// The pyramid split into 2 tets along the base diagonal 0-2 (diagonal 0)
/// or 1-3 (diagonal 1).
std::array<LocalTet, 2> pyramid_decomposition(int diagonal);

}  // namespace femorph
