// Internals of Tet To Hex (thesis 4.5), shared by its step files:
//   build_tet_adjacency.cpp            faces shared by two tets (LINK edges)
//   build_search_trees.cpp             the search trees of Fig. 4.10
//   search_candidates.cpp              A1, the local search
//   candidate_priority.cpp             Eq. 4.1
//   adopt_candidates_greedy.cpp        A2, GMax
//   count_nonconformal_interfaces.cpp  quad faces meeting two triangles
//   dissolve_nonconformal_cells.cpp    refuse_nonconformal
//   recombine_tetrahedra.cpp           the driver
// Not installed; tests may include it.
#pragma once

#include "common/types.h"
#include "hex/hex_decomposition_types.h"
#include "hex/tet_to_hex.h"
#include "quality/tet_quality.h"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace femorph {
namespace tet_to_hex {

constexpr int kMaxTets = 6;    // tets of a candidate (hexahedron types B-F)
constexpr int kMaxNodes = 8;   // nodes of a candidate (hexahedron)
constexpr int kMaxQuads = 6;   // quad faces of a candidate (hexahedron)

/// Face adjacency of a tet mesh: adjacency[4 t + f] = 4 n + g when the face
/// of tet t opposite its local vertex f is the face of tet n opposite g (the
/// LINK edges of the extended RF-graph, 4.5.2), -1 on the boundary. Fails
/// on a tet referring to a missing point, a face shared by more than two
/// tets, or two tets on the same side of a face (overlapping or
/// inconsistently oriented tets).
Status build_tet_adjacency(index_t num_points, const std::vector<Tet>& tets,
                           std::vector<index_t>& adjacency);

/// One search tree of Fig. 4.10 (generated from the decomposition tables,
/// see build_search_trees.cpp): a triangulation of a reference cell whose
/// tets are listed in walk order, each after the first sharing a face with
/// an earlier one. Labels are the cell's VTK node ids.
struct SearchTree {
  CellKind kind = CellKind::Hexahedron;
  /// Hexahedra: the Fig. 4.5 type of the triangulation and whether it is the
  /// "-" variant; wedges and pyramids: -1 and false.
  int decomposition = -1;
  bool mirrored = false;
  int num_tets = 0, num_nodes = 0, num_quads = 0;
  std::array<LocalTet, kMaxTets> tets{};  // positive on the reference cell
  /// Step s >= 1 crosses from tets[parent[s]] through its face opposite label
  /// opposite[s] into tets[s], whose fourth label is apex[s].
  std::array<std::int8_t, kMaxTets> parent{}, opposite{}, apex{};
  /// Quad faces in VTK's face order (outward) and the diagonal splitting
  /// each (0: nodes 0-2, 1: nodes 1-3); quads_after_step[s] has bit q when
  /// both triangles of quad q are known after step s (QUAD checked there).
  std::array<std::array<std::int8_t, 4>, kMaxQuads> quads{};
  std::array<std::uint8_t, kMaxQuads> quad_diagonal{};
  std::array<std::uint8_t, kMaxTets> quads_after_step{};
  /// Orientation-preserving maps of a root tet onto tets[0]: assignment[a][k]
  /// is the label of the root's local vertex k. One per class under the
  /// triangulation's rotations fixing tets[0] (equivalent maps give the
  /// same candidate).
  std::vector<std::array<std::int8_t, 4>> assignments;
};

/// Every search tree: for each triangulation class of the hexahedron (the
/// twelve of Fig. 4.5 up to rotations), the wedge and the pyramid, one tree
/// per class of tets under the triangulation's rotations, rooted there.
const std::vector<SearchTree>& search_trees();

/// The quad faces of a cell kind in VTK order (pyramid: the base,
/// (0, 3, 2, 1) outward); returns their count (0 for tets).
int cell_quads(CellKind kind, const std::array<std::int8_t, 4>*& quads);

/// A walk of one search tree from one root (A1).
struct Walk {
  std::array<index_t, kMaxNodes> node;  // label -> mesh vertex
  std::array<index_t, kMaxTets> tet;    // step -> mesh tet
};

/// The mesh around `root` for the tree and assignment: LINK across the
/// tree's faces, every label one distinct vertex, every tet distinct and of
/// larger id than the root (a candidate is reported by its smallest tet
/// only), QUAD(cos >= min_cos) as soon as both triangles of a quad are
/// known. False at the first failure.
bool walk_search_tree(const SearchTree& tree, const std::array<std::int8_t, 4>& assignment,
                      index_t root, const Vec3* points, const Tet* tets,
                      const index_t* adjacency, double min_cos, Walk& walk);

/// A candidate found by A1 that passed the minimum scaled Jacobian.
struct Candidate {
  double priority = 0;                  // Eq. 4.1
  std::array<index_t, kMaxTets> tets{};  // sorted; tets[0] the root
  std::uint16_t tree = 0;               // index into search_trees()
  std::uint8_t assignment = 0;          // index into the tree's assignments
  std::uint8_t num_tets = 0;
};

/// Eq. 4.1 for a successful walk: mean cos of the quads' dihedral angles
/// over 2, plus the mean over quads of the smallest sine of their interior
/// angles over 2, plus gamma_type (10 hexahedron, 4 wedge, 0 pyramid).
double candidate_priority(const SearchTree& tree, const Walk& walk, const Vec3* points);

/// A1 over every root tet (in parallel): the candidates of the enabled kinds
/// whose minimum scaled Jacobian reaches params.min_scaled_jacobian, one
/// per set of tets (the best priority when several cells share the tets),
/// ordered by their sorted tets (lexicographically). stats.candidates counts the cells the search found,
/// stats.admissible those kept.
/// progress (may be empty) gets the fraction of roots done, from the calling
/// thread; when it returns false the search stops and returns false.
bool search_candidates(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                       const std::vector<index_t>& adjacency, const TetToHexParams& params,
                       std::vector<Candidate>& candidates, TetToHexStats& stats,
                       const std::function<bool(double)>& progress = {});

/// Sorts candidates by decreasing priority, ties by their sorted tet ids
/// (stable: the input must be ordered by tets, as search_candidates gives).
void sort_candidates(std::vector<Candidate>& candidates);

/// An adopted candidate as a cell.
struct Cell {
  CellKind kind = CellKind::Hexahedron;
  std::array<index_t, kMaxNodes> nodes{};  // VTK order
  std::array<index_t, kMaxTets> tets{};
  int num_tets = 0;
  index_t candidate = kInvalidIndex;  // index into the sorted candidates
  bool alive = true;                  // false once dissolved
};

/// The cell of a candidate (replays its walk).
Cell candidate_cell(const Candidate& candidate, index_t index, const std::vector<Vec3>& points,
                    const std::vector<Tet>& tets, const std::vector<index_t>& adjacency);

/// A2 (GMax, 4.5.4): candidates in priority order, each adopted when all its
/// tets are still free. cell_of_tet (#T, -1 free) gets the index into
/// `cells` of the adopted cell owning each tet.
void adopt_candidates_greedy(const std::vector<Candidate>& candidates,
                             const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                             const std::vector<index_t>& adjacency, std::vector<Cell>& cells,
                             std::vector<index_t>& cell_of_tet);

/// The tets across the two triangles of quad q (index into cell_quads) of a
/// cell (kInvalidIndex on the boundary); false if the cell's tets do not
/// have the quad's two triangles.
bool quad_across(const Cell& cell, int q, const std::vector<Tet>& tets,
                 const std::vector<index_t>& adjacency, std::array<index_t, 2>& across);

/// Whether quad q (index into cell_quads) of a cell is conformal: on the
/// boundary (both triangles), or both triangles facing one live cell that
/// has a quad on the same four vertices.
bool quad_is_conformal(const Cell& cell, int q, const std::vector<Cell>& cells,
                       const std::vector<index_t>& cell_of_tet, const std::vector<Tet>& tets,
                       const std::vector<index_t>& adjacency);

/// Quad faces of live cells that are not conformal; flags (when not null,
/// #cells) marks the cells having one.
std::size_t count_nonconformal_interfaces(const std::vector<Cell>& cells,
                                          const std::vector<index_t>& cell_of_tet,
                                          const std::vector<Tet>& tets,
                                          const std::vector<index_t>& adjacency,
                                          std::vector<std::uint8_t>* flags = nullptr);

/// refuse_nonconformal: until no live cell has a non-conformal quad, adopt
/// (priority order) the free candidates on the two tets behind an offending
/// quad whose own quads are all conformal (a pyramid capping a hexahedron's
/// quad that faces tets), for cells all of whose offending quads have one;
/// then dissolve the cells still offending into their tets (never adopted
/// again). Last, adopt the candidates on free tets whose quads are all
/// conformal (priority order). Returns the number of cells dissolved.
std::size_t dissolve_nonconformal_cells(const std::vector<Candidate>& candidates,
                                        const std::vector<Vec3>& points,
                                        const std::vector<Tet>& tets,
                                        const std::vector<index_t>& adjacency,
                                        std::vector<Cell>& cells,
                                        std::vector<index_t>& cell_of_tet);

}  // namespace tet_to_hex
}  // namespace femorph
