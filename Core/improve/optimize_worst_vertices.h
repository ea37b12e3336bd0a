// Beyond the thesis: local optimisation of the inner vertices of the worst
// tets. ODT (Eq. 2.31) uses barycentres next to the boundary (Fig. 2.33 (b)),
// which leaves the tets with a boundary face and one inner vertex where they
// are; a compass search on the vertex position maximising the minimum
// stretch (Eq. 1.1) of its ball lifts them.
#pragma once

#include "common/types.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femorph {

class MovingBall;
class TetMesh;

struct WorstVertexOptions {
  /// Inner vertices of tets with stretch below this are optimised.
  double threshold = 0.35;
  /// Passes over the worst tets.
  int passes = 3;
  /// Per vertex slot; only vertices with mask 1 move. Empty: every inner vertex.
  std::vector<std::uint8_t> vertex_mask;
};

struct WorstVertexStats {
  std::size_t candidates = 0;  ///< vertex visits
  std::size_t improved = 0;    ///< visits that raised the ball's minimum stretch
};

/// For each inner vertex of a tet below the threshold: a compass search (the
/// six axis directions, step a quarter of the mean edge length, halved ten
/// times) moving the vertex while the minimum stretch of its ball rises. Every
/// accepted position keeps the ball positive (exact test). Deterministic.
WorstVertexStats optimize_worst_vertices(TetMesh& mesh, const WorstVertexOptions& options = {});

/// The compass search of the two functions below, on a ball given: from
/// *x, the six axis directions with `step`, halved ten times, moving *x
/// while the ball's minimum stretch rises. Returns that minimum at the
/// final *x (and the one at the start in *start_min). Read only on the mesh
/// (the caller applies the move).
double compass_search(MovingBall& ball, double step, Vec3* x, double* start_min = nullptr);

/// The first step of the compass search at x: a quarter of the mean
/// distance from x to `neighbours` (sorted and made unique here).
double compass_start_step(const TetMesh& mesh, std::vector<index_t>& neighbours, const Vec3& x);

/// Moves inner vertex v by compass search (axis directions, step a quarter
/// of its mean edge length, halved ten times) while the minimum stretch of
/// its ball rises; keeps the ball positive (exact test). Returns the new
/// minimum stretch of the ball.
double compass_search_vertex(TetMesh& mesh, index_t v);

}  // namespace femorph
