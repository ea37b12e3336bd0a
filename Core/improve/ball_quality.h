// The quality of a vertex's ball (its incident tets) with the vertex moved:
// the quality guard every smoothing and relocation step of Improve shares.
#pragma once

#include "common/types.h"
#include "mesh/tet_mesh.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace femorph {

class TetMesh;

/// Minimum stretch (Eq. 1.1) over the tets of `ball` with vertex v placed at
/// p (v = kInvalidIndex: the tets as they are).
double ball_min_stretch(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p);

/// The ball of vertex v with v free to move, for searches that try many
/// positions of v (compass_search_vertex): per tet, the three other
/// vertices in an order that keeps the orientation, and what does not
/// depend on v (the opposite face's area, its longest edge) computed once.
/// Stretches agree with tet_stretch to rounding.
class MovingBall {
 public:
  MovingBall(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v);
  /// The ball of a vertex v that would split the inner edge (a, b), before
  /// the split (read only): each tet of the edge's ring becomes two, with v
  /// in a's place and in b's (TetMesh::split_edge); the search order starts
  /// from the stretches with v at `start`.
  MovingBall(const TetMesh& mesh, const std::vector<index_t>& ring, index_t a, index_t b, const Vec3& start);
  /// Minimum stretch (Eq. 1.1) over the ball with v at p.
  double min_stretch(const Vec3& p) const;
  /// Whether the minimum stretch with v at p exceeds `bound` (then it is
  /// written to *min). Tries the tets in the order of their stretch at v's
  /// position, lowest first, and moves to the front the tet that stopped a
  /// try and the lowest at a position that exceeded; stops at the first tet
  /// at or below `bound`: the tets that limit a search change little, so
  /// most rejected positions cost one or two tets instead of the ball.
  bool exceeds(const Vec3& p, double bound, double* min);

 private:
  struct Opposite {
    Vec3 a, b, c;          ///< (v, a, b, c) has the tet's orientation
    double max_squared;    ///< longest of ab, ac, bc, squared
    double area2;          ///< |ab x ac|: twice the area of face abc
  };
  double stretch(const Opposite& o, const Vec3& p) const;
  void add(const TetMesh& mesh, index_t t, int local);  ///< tet t with v at its local vertex `local`
  void start_order(const Vec3& p);  ///< the search order for v at p
  std::vector<Opposite> opposite_;
  std::vector<std::uint32_t> order_;  ///< the order exceeds() tries the tets in
};

/// The quality guard of the smoothing steps (beyond the thesis): moving v
/// to p must not lower the ball's minimum stretch (`old_min`, from
/// ball_min_stretch at v's position), and no tet of the ball at or above
/// `floor` may fall below it. Without the second rule a ball that already
/// holds a near-flat tet lets a move spoil its good tets down to that tet's
/// level (seen on a real part, fandisk, with jittered inner vertices).
bool move_keeps_quality(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p,
                        double old_min, double floor);

/// move_keeps_quality that also writes the ball's stretches with v at p
/// (ball order) into `stretch` when it returns true.
bool move_keeps_quality(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p,
                        double old_min, double floor, std::vector<double>& stretch);

/// The step-size rule of the ODT smoothers (Fig. 2.33; Eqs. 2.31, 2.34):
/// alpha = 1, halved up to `max_halvings` times. candidate(alpha, &p) gives
/// v's position for the step alpha (false: none for this alpha); the first
/// one that passes the quality guard (when `quality_guard`, with
/// move_keeps_quality(.., old_min, floor), `old_min` being the ball's
/// minimum stretch at v's position), then accept(p) (a costlier test, asked
/// last), and keeps every tet of the ball positive
/// (TetMesh::move_vertex_in_ball, exact) is taken. `ball` is v's whole
/// ball. With `stretch` and the guard, the ball's new stretches (ball
/// order) are left there when v moves, for a caller that keeps stretches
/// per tet. Returns the accepted alpha, 0 when v stayed; *halvings counts
/// the halvings tried.
template <class Candidate, class Accept>
double move_with_step_halving(TetMesh& mesh, const std::vector<index_t>& ball, index_t v, int max_halvings,
                              bool quality_guard, double floor, double old_min, Candidate&& candidate,
                              Accept&& accept, std::vector<double>* stretch, std::size_t* halvings) {
  double alpha = 1;
  for (int h = 0; h <= max_halvings; ++h, alpha *= 0.5) {
    if (h > 0 && halvings) ++*halvings;
    Vec3 p;
    if (!candidate(alpha, &p)) continue;
    if (quality_guard && !(stretch ? move_keeps_quality(mesh, ball, v, p, old_min, floor, *stretch)
                                   : move_keeps_quality(mesh, ball, v, p, old_min, floor)))
      continue;
    if (!accept(static_cast<const Vec3&>(p))) continue;
    if (mesh.move_vertex_in_ball(v, p, ball) == OpStatus::Ok) return alpha;
  }
  return 0;
}

/// The same with the ball's minimum stretch found here.
template <class Candidate, class Accept>
double move_with_step_halving(TetMesh& mesh, const std::vector<index_t>& ball, index_t v, int max_halvings,
                              bool quality_guard, double floor, Candidate&& candidate, Accept&& accept,
                              std::size_t* halvings) {
  const double old_min = quality_guard ? ball_min_stretch(mesh, ball, v, mesh.point(v)) : 0;
  return move_with_step_halving(mesh, ball, v, max_halvings, quality_guard, floor, old_min,
                                std::forward<Candidate>(candidate), std::forward<Accept>(accept), nullptr, halvings);
}

/// The same without a last test.
template <class Candidate>
double move_with_step_halving(TetMesh& mesh, const std::vector<index_t>& ball, index_t v, int max_halvings,
                              bool quality_guard, double floor, Candidate&& candidate, std::size_t* halvings) {
  return move_with_step_halving(
      mesh, ball, v, max_halvings, quality_guard, floor, std::forward<Candidate>(candidate),
      [](const Vec3&) { return true; }, halvings);
}

}  // namespace femorph
