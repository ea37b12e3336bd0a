// Degenerated element removal, thesis 2.6.2 (Fig. 2.38): slivers by double
// split collapse, caps and spades by split collapse [Li 2003], driven by a
// min-heap on stretch (Eq. 1.1) below a threshold (0.05 in the thesis).
#pragma once

#include "common/types.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace femorph {

class TetMesh;

/// Moves a boundary vertex onto the fitted surface or curve it lies on
/// (thesis 2.6.1.3: "the new vertex is moved onto the fitted surface").
/// Receives the vertex id and a proposed position, returns the projected
/// position. Inner vertices are never passed.
using ProjectVertexFn = std::function<Vec3(index_t vertex, const Vec3& position)>;

/// Shapes of a flat tet, thesis Fig. 2.38.
enum class DegenerateKind : std::uint8_t { Sliver = 0, Cap = 1, Spade = 2 };
const char* to_string(DegenerateKind kind);

/// Classification of a flat tet and the edges its removal operation uses.
/// Indices are local (0..3) into the four points given to the classifier.
struct DegenerateShape {
  DegenerateKind kind = DegenerateKind::Sliver;
  /// Sliver: the two opposite edges that cross, (v[0], v[1]) and (v[2], v[3]).
  /// Cap / spade: the split edge (v[0], v[1]) shared by the largest and the
  /// smallest face, the apex v[2] (the smallest face's third vertex, which
  /// the new vertex is collapsed with) and the remaining vertex v[3].
  std::array<int, 4> v{{0, 1, 2, 3}};
  /// Split parameters: the new vertex of edge (v[0], v[1]) is at
  /// p[v0] + s (p[v1] - p[v0]); for a sliver the one of (v[2], v[3]) at
  /// p[v2] + t (p[v3] - p[v2]). Closest points of the two lines (sliver), or
  /// the projection of the apex onto the edge (cap, spade); not clamped.
  double s = 0.5;
  double t = 0.5;
};

/// Classifies a tet by its shape (thesis Fig. 2.38), meant for tets whose
/// four vertices lie near a plane (low stretch):
///   spade  three vertices near a line: some face's smallest height (twice
///          its area over its longest edge) is below spade_tolerance times
///          the tet's longest edge;
///   sliver otherwise, when projected onto the plane of the largest face two
///          opposite edges cross (the four points form a convex quadrangle);
///   cap    otherwise: one vertex projects inside the triangle of the other
///          three.
DegenerateShape classify_degenerate_tet(const std::array<Vec3, 4>& p, double spade_tolerance = 0.1);

struct DegenerateRemovalOptions {
  /// gamma_st of Step 1: tets with stretch below it are removed (thesis: 0.05,
  /// the recommended lower limit).
  double stretch_threshold = 0.05;
  /// See classify_degenerate_tet().
  double spade_tolerance = 0.1;
  /// Split points closer than this fraction of the edge to an endpoint are
  /// not made: the apex is collapsed with that endpoint instead (the split
  /// would create an almost zero-length edge).
  double min_split_fraction = 0.1;
  /// Optional projection of new and moved boundary vertices onto fitted
  /// surfaces. Empty: boundary vertices stay on the segment or face they come
  /// from (exact for planar parts).
  ProjectVertexFn project;
  /// Safety bound on successful operations; 0: 20 per initial heap entry + 100.
  std::size_t max_operations = 0;
  /// Restriction to a region: one flag per vertex slot; only tets whose four
  /// vertices are flagged are removed (vertices a split creates count as
  /// flagged). Empty: every tet.
  std::vector<std::uint8_t> vertex_mask;
  /// When set: the vertices of every tet an accepted operation made or
  /// changed are set to 1 (the vector grows as needed), as
  /// DensityControlOptions::touched.
  std::vector<char>* touched = nullptr;
};

struct DegenerateRemovalStats {
  std::size_t initial_below = 0;     ///< tets below the threshold at the start (positive ones)
  std::size_t removed_slivers = 0;   ///< successful double split collapses
  std::size_t removed_caps = 0;      ///< successful split collapses on caps
  std::size_t removed_spades = 0;    ///< successful split collapses on spades
  std::size_t failed = 0;            ///< popped tets no operation could remove
  std::size_t remaining_below = 0;   ///< live positive tets still below the threshold
  /// Over the live tets it may change: all of them, or those whose
  /// vertices are all in vertex_mask.
  double min_stretch_before = 0;
  double min_stretch_after = 0;
};

/// Thesis 2.6.2, Steps 1-4: pushes the tets with stretch below the threshold
/// on a min-heap, pops the worst, classifies it (sliver, cap, spade), removes
/// it by double split collapse or split collapse, and pushes the affected
/// tets that fall below the threshold; until the heap is empty. An operation
/// that fails is undone (its splits are collapsed back) and the tet stays.
/// Collapses follow the rules of Fig. 2.37 (TetMesh::plan_collapse_by_rules),
/// so boundary vertices only move along their boundary segment or face
/// (projected by `project` when given). Inverted tets are left to
/// remove_inverted_elements(). Deterministic.
DegenerateRemovalStats remove_degenerate_elements(TetMesh& mesh, const DegenerateRemovalOptions& options = {});

}  // namespace femorph
