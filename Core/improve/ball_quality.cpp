#include "improve/ball_quality.h"

#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <limits>

namespace femorph {

namespace {

double stretch_with(const TetMesh& mesh, index_t t, index_t v, const Vec3& p) {
  const Tet& T = mesh.tet(t);
  const Vec3* x[4];
  for (int i = 0; i < 4; ++i) x[i] = T[i] == v ? &p : &mesh.point(T[i]);
  return tet_stretch(*x[0], *x[1], *x[2], *x[3]);
}

/// move_keeps_quality's test of one tet t of the ball; *q: its stretch with
/// v at p.
bool tet_keeps_quality(const TetMesh& mesh, index_t t, index_t v, const Vec3& p, double old_min, double floor,
                       double* q) {
  *q = stretch_with(mesh, t, v, p);
  if (*q < old_min) return false;
  return !(*q < floor && stretch_with(mesh, t, kInvalidIndex, p) >= floor);
}

}  // namespace

double ball_min_stretch(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p) {
  double q = std::numeric_limits<double>::infinity();
  for (const index_t t : ball) q = std::min(q, stretch_with(mesh, t, v, p));
  return q;
}

bool move_keeps_quality(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p,
                        double old_min, double floor) {
  double q;
  for (const index_t t : ball)
    if (!tet_keeps_quality(mesh, t, v, p, old_min, floor, &q)) return false;
  return true;
}

bool move_keeps_quality(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p,
                        double old_min, double floor, std::vector<double>& stretch) {
  stretch.resize(ball.size());
  for (std::size_t k = 0; k < ball.size(); ++k)
    if (!tet_keeps_quality(mesh, ball[k], v, p, old_min, floor, &stretch[k])) return false;
  return true;
}

}  // namespace femorph
