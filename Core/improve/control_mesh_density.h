// Mesh density control, thesis 2.6.3 Fig. 2.40 (c): edges too long for the
// target mesh density field are split, edges too short collapsed.
//
// With rho_GC(c_e) the density of the target field (DensityGrid) at the
// midpoint c_e of edge e and the density thresholds beta1, beta2:
//   Steps 1-3 (split_long_edges): edges with L(e) >= beta1 / rho_GC(c_e) go
//     into a max-heap by length; the longest is popped and split at its
//     midpoint until the heap is empty (beyond the thesis, a half of an edge
//     the pass started with is pushed again while still long).
//   Steps 4-7 (collapse_short_edges): edges with L(e) <= beta2 / rho_GC(c_e)
//     go into a min-heap; the shortest is popped and collapsed (rules of
//     Fig. 2.37, collapse_edge_by_rules); the edges of the surviving vertex
//     that now qualify are pushed; until the heap is empty.
// control_mesh_density() repeats both passes until neither changes the mesh
// (in the thesis the passes run inside Phased ODT smoothing until no more
// density control happens) or the iteration limit is reached. The passes
// converge when beta1 > 2 beta2 and 1 + beta2 / 2 < beta1 (thesis 2.6.3);
// the defaults 1.5 and 0.67 satisfy both.
//
// Beyond the thesis: a collapse is refused when an edge of the surviving
// vertex would qualify for splitting (without this guard a split and a
// collapse can undo each other forever), and for an edge whose ends have the
// same class the two half-edge collapses (Fig. 2.39) are tried besides the
// midpoint of rule (G), taking the admissible one with the best stretch.
// An operation is also refused when it would create a tet of
// stretch (Eq. 1.1) below `min_stretch` that is also worse than the worst tet
// it replaces (a split: than half of it, `split_relative_floor`; so a region
// that is already poor can still be refined), and
// splits and collapses on the boundary keep the boundary's shape: a midpoint
// of a planar boundary edge lies on the plane; curved regions need the
// `project` callback.
#pragma once

#include "common/types.h"
#include "improve/mesh_density.h"

#include <cstddef>
#include <functional>
#include <vector>

namespace femorph {

class TetMesh;

struct DensityControlOptions {
  double split_threshold = 1.5;      ///< beta1^MD
  double collapse_threshold = 0.67;  ///< beta2^MD
  /// Refuse operations creating a tet with stretch below this (and below the
  /// worst stretch of the tets they replace). <= 0: only validity checks.
  double min_stretch = 0.05;
  /// A split is refused only when its worst new tet is below min_stretch and
  /// below this fraction of the worst tet it replaces. Beyond the thesis: the
  /// long edge is what makes its ring poor, and the smoothing and the
  /// degenerate removal that follow repair the halves; a split refused
  /// leaves the region coarse for good (a boss top stretched x3 stayed flat
  /// with 1.0).
  double split_relative_floor = 0.5;
  /// Beyond the thesis: a split pass pushes the halves of the edges it
  /// started with back into its heap while they are still long (one pass
  /// then halves an edge twice, as a x3 stretch needs). false: the thesis'
  /// steps 1-3, each edge halved once per pass.
  bool resplit_halves = true;
  /// Beyond the thesis: with resplit_halves, an edge the pass started with
  /// whose scaled length L rho is in [2.5, 3.5) is split at a third (from
  /// its lower vertex id) and its longer part then in half: three pieces,
  /// the number nearest the target there (n pieces are |n / (L rho) - 1|
  /// off), where halving made two or four (an edge at 3 / rho made four of
  /// 0.75 / rho, which no collapse takes back).
  bool split_in_thirds = true;
  /// Beyond the thesis: a split pass merges an inner midpoint into an inner
  /// vertex it made earlier when the two are closer than beta2 of the
  /// target (plan_merge in control_mesh_density.cpp): the split and the
  /// merge are made as one TetMesh::flip_edge_to_fan, without the midpoint.
  bool merge_new_midpoints = true;
  /// When set: every vertex whose position or neighbours an accepted split,
  /// merge or collapse changed is set to 1 (the vector grows as needed), so
  /// a caller can smooth just there.
  std::vector<char>* touched = nullptr;
  /// Rounds of split pass + collapse pass.
  int max_iterations = 20;
  /// How rho_GC is read (the thesis: Cell).
  DensityLookup lookup = DensityLookup::Cell;
  /// Projection of a new boundary vertex (after a split, or the kept vertex
  /// of a boundary collapse when it moves) onto its curved region:
  /// (vertex id, position) -> projected position. Applied only when the
  /// result keeps every tet valid and above the stretch floor. Empty: none
  /// (right for planar regions).
  std::function<Vec3(index_t vertex, const Vec3& position)> project;
  /// `project` may be called from several threads at once (read only on
  /// the mesh, no shared scratch): the collapse pass then projects while it
  /// evaluates its candidates in parallel, instead of evaluating a boundary
  /// candidate again, serially, when it is committed.
  bool project_in_parallel = false;
  /// Extra test of a collapse of a boundary vertex (keep, remove; keep
  /// placed at x; the balls of both ends): false refuses that position.
  /// Phased ODT uses it for the chord error (2.6.4). Empty: none.
  std::function<bool(index_t keep, index_t remove, const Vec3& x, const std::vector<index_t>& ball_keep,
                     const std::vector<index_t>& ball_remove)>
      accept_boundary_collapse;
  /// Restriction to a region: one flag per vertex slot; only edges whose two
  /// vertices are flagged are split or collapsed (vertices a split creates
  /// inherit the flag). Empty: every edge.
  std::vector<char> vertex_mask;
  /// Beyond the mask: long inner edges (on no boundary face) are split even
  /// when an end is not flagged; the new vertex is inner and flagged, the
  /// boundary does not change. Adapt: edges from a fixed object surface into
  /// the space would otherwise only ever stretch.
  bool split_inner_edges = false;
  /// A check for tests: the collapse pass also looks up every heap entry it
  /// takes as current without a lookup (neither end moved since it was
  /// queued; DensityControlStats::queue_checked) and counts those no longer
  /// short or of another length (queue_disagreements: 0 unless that
  /// bookkeeping is wrong).
  bool check_queue = false;
  /// Measure Eq. 2.35 before and after (error_before/after); off for
  /// callers that measure it themselves (two passes over every edge).
  bool measure_error = true;
};

struct DensityControlStats {
  std::size_t splits = 0;
  std::size_t collapses = 0;
  std::size_t refused_splits = 0;       ///< by validity or the stretch floor
  std::size_t merged_midpoints = 0;     ///< splits whose midpoint merged (merge_new_midpoints)
  std::size_t refused_collapses = 0;    ///< by Fig. 2.37, link, validity, floor
  std::size_t projections = 0;          ///< project callbacks applied
  std::size_t queue_checked = 0;        ///< with check_queue only
  std::size_t queue_disagreements = 0;  ///< with check_queue only
  int iterations = 0;
  bool converged = false;  ///< the last round changed nothing
  DensityError error_before;  ///< Eq. 2.35, with options.lookup
  DensityError error_after;
};

/// Steps 1-3: splits every edge with L(e) * rho_GC(c_e) >= beta1, longest
/// first. Returns the number of splits; refusals are added to *stats.
std::size_t split_long_edges(TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                             std::vector<char>& mask, DensityControlStats* stats);

/// Steps 4-7: collapses edges with L(e) * rho_GC(c_e) <= beta2, shortest
/// first, re-checking the edges around each surviving vertex. Returns the
/// number of collapses; refusals are added to *stats.
std::size_t collapse_short_edges(TetMesh& mesh, const DensityGrid& grid, const DensityControlOptions& options,
                                 const std::vector<char>& mask, DensityControlStats* stats);

/// Mesh density control (thesis 2.6.3): rounds of split_long_edges and
/// collapse_short_edges until a round changes nothing or max_iterations.
/// `grid` is the target field (DensityGrid::build from the deformed mesh and
/// the original vertex densities). The mesh stays valid (every operation is
/// validated by TetMesh); vertex ids of dead slots may be reused.
DensityControlStats control_mesh_density(TetMesh& mesh, const DensityGrid& grid,
                                         const DensityControlOptions& options = {});

}  // namespace femorph
