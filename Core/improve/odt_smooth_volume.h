// ODT vertex repositioning of the inner vertices (thesis 2.6.1.1 Eq. 2.31,
// 2.6.5.4 tetrahedron improvement).
#pragma once

#include "common/types.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace femorph {

class TetMesh;

struct OdtSmoothOptions {
  /// Gauss-Seidel sweeps over the vertices (the thesis: two or three per step).
  int iterations = 3;
  /// Per vertex slot: only vertices with mask 1 move (region restriction).
  /// Empty: every inner vertex may move.
  std::vector<std::uint8_t> vertex_mask;
  /// Density rho at a point (Eq. 2.29-2.31), evaluated at each tet's
  /// barycentre to give rho_tau. Empty: uniform density 1.
  std::function<double(const Vec3&)> density;
  /// Per vertex slot density; rho_tau is the mean over the tet's four
  /// vertices. Used when `density` is empty and this is not.
  std::vector<double> vertex_density;
  /// Stop when no vertex moved farther than tolerance times the mean length
  /// of its edges in a sweep.
  double tolerance = 1e-4;
  /// Beyond the thesis: after the first sweep only vertices near a move
  /// are visited again -- those whose own or a neighbour's last accepted
  /// move was farther than this times its mean edge length (an active set;
  /// 0: every vertex in every sweep).
  double active_tolerance = 0.02;
  /// Step halvings of alpha_ODT (Eq. 2.31) before a vertex is left in place.
  int max_halvings = 6;
  /// Quality guard: accept a step only when the minimum stretch (Eq. 1.1)
  /// over the vertex's ball does not decrease. This makes the minimum stretch
  /// of the mesh monotone; off gives the thesis' plain rule (step halved only
  /// against inversion).
  bool quality_guard = true;
  /// With the guard, no tet of the ball at or above this stretch may fall
  /// below it (move_keeps_quality()). Off (0) for inner vertices: the rule
  /// blocks moves that ODT needs (fandisk with its inner vertices jittered
  /// keeps a lower minimum with it); the boundary phases use it.
  double quality_floor = 0;
  /// Beyond the thesis (relax_edge_lengths): when set, a vertex moves toward
  /// the rest position of springs along its edges instead of Eq. 2.31's
  /// centre, each spring as long as 1 / edge_density at the edge's midpoint:
  ///   x_new = (1 - a) x + a mean_w (p_w + (x - p_w) / (rho_e |x - p_w|)).
  std::function<double(const Vec3&)> edge_density;
  /// With the guard: a ball whose minimum stretch is above guard_keep may
  /// lose up to this fraction of it, down to guard_keep (0: the minimum may
  /// not drop). The springs of edge_density do not shape tets; a strict
  /// guard refuses most of their moves.
  double guard_drop = 0;
  double guard_keep = 0.35;
};

struct OdtSmoothReport {
  int sweeps = 0;               // sweeps run
  std::size_t moved = 0;        // accepted moves, summed over sweeps
  std::size_t refused = 0;      // vertices left in place after max_halvings
  std::size_t halvings = 0;     // step halvings, summed
  double last_max_step = 0;     // largest relative move of the last sweep
  bool converged = false;       // last_max_step <= tolerance
  // With BoundarySmoothOptions::check_stretch_cache (tests): the ball
  // minima read from the kept stretches, and those that differ from the
  // mesh's.
  std::size_t cache_checked = 0, cache_disagreements = 0;
};

/// Moves each free inner vertex toward the density-weighted mean of the
/// centres c_tau of its ball (Eq. 2.31):
///   x_new = (1 - a) x + a sum(|tau| rho_tau c_tau) / sum(|tau| rho_tau),
/// c_tau the circumcentre, or the barycentre when tau has a boundary vertex
/// (Fig. 2.33 (b)) or is not locally Delaunay (2.6.5.4: a neighbour's
/// opposite vertex strictly inside its circumsphere, exact test). a starts at
/// 1 and is halved while the move would invert a tet (TetMesh::move_vertex,
/// exact) or, with the quality guard, lower the ball's minimum stretch.
/// Beyond the thesis, for speed: vertices are visited colour by colour
/// (greedy colouring in id order, no two vertices of a colour in one tet),
/// each colour in parallel, and the Delaunay test is made once per tet and
/// sweep, at its start. The result does not depend on the number of
/// threads.
OdtSmoothReport odt_smooth_volume(TetMesh& mesh, const OdtSmoothOptions& options = {});

}  // namespace femorph
