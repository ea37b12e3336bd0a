#include "improve/ball_quality.h"

#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
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

MovingBall::MovingBall(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v) {
  opposite_.reserve(ball.size());
  for (const index_t t : ball) add(mesh, t, mesh.local_index(t, v));
  start_order(mesh.point(v));
}

MovingBall::MovingBall(const TetMesh& mesh, const std::vector<index_t>& ring, index_t a, index_t b,
                       const Vec3& start) {
  opposite_.reserve(2 * ring.size());
  for (const index_t t : ring) {
    add(mesh, t, mesh.local_index(t, a));
    add(mesh, t, mesh.local_index(t, b));
  }
  start_order(start);
}

void MovingBall::add(const TetMesh& mesh, index_t t, int local) {
  // (v, a, b, c) an even permutation of the tet for v at local index 0..3.
  static constexpr int kOrder[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {2, 1, 0}};
  const Tet& T = mesh.tet(t);
  Opposite o;
  o.a = mesh.point(T[kOrder[local][0]]);
  o.b = mesh.point(T[kOrder[local][1]]);
  o.c = mesh.point(T[kOrder[local][2]]);
  const Vec3 ab = o.b - o.a, ac = o.c - o.a;
  o.max_squared = std::max({ab.squaredNorm(), ac.squaredNorm(), (o.c - o.b).squaredNorm()});
  o.area2 = ab.cross(ac).norm();
  opposite_.push_back(o);
}

void MovingBall::start_order(const Vec3& p) {
  std::vector<double> at(opposite_.size());
  order_.resize(opposite_.size());
  for (std::size_t k = 0; k < opposite_.size(); ++k) {
    order_[k] = static_cast<std::uint32_t>(k);
    at[k] = stretch(opposite_[k], p);
  }
  std::sort(order_.begin(), order_.end(), [&at](std::uint32_t x, std::uint32_t y) { return at[x] < at[y]; });
}

// Eq. 1.1 as tet_stretch computes it, 2 sqrt(6) det / (L_max S), with the
// parts of the opposite face taken from `o`.
double MovingBall::stretch(const Opposite& o, const Vec3& p) const {
  static const double kScale = 2.0 * std::sqrt(6.0);
  // Scalars throughout: Eigen's cross().norm() stores and reloads the
  // components, a store-forwarding stall (see tet_quality.cpp).
  const double ax = o.a.x() - p.x(), ay = o.a.y() - p.y(), az = o.a.z() - p.z();
  const double bx = o.b.x() - p.x(), by = o.b.y() - p.y(), bz = o.b.z() - p.z();
  const double cx = o.c.x() - p.x(), cy = o.c.y() - p.y(), cz = o.c.z() - p.z();
  const double nx = by * cz - bz * cy, ny = bz * cx - bx * cz, nz = bx * cy - by * cx;  // pb x pc
  const double det = ax * nx + ay * ny + az * nz;
  const double ux = ay * bz - az * by, uy = az * bx - ax * bz, uz = ax * by - ay * bx;  // pa x pb
  const double wx = ay * cz - az * cy, wy = az * cx - ax * cz, wz = ax * cy - ay * cx;  // pa x pc
  const double l2 = std::max(std::max(o.max_squared, ax * ax + ay * ay + az * az),
                             std::max(bx * bx + by * by + bz * bz, cx * cx + cy * cy + cz * cz));
  const double s = o.area2 + std::sqrt(nx * nx + ny * ny + nz * nz) + std::sqrt(ux * ux + uy * uy + uz * uz) +
                   std::sqrt(wx * wx + wy * wy + wz * wz);
  const double denominator = std::sqrt(l2) * s;
  return denominator > 0 ? kScale * det / denominator : 0.0;
}

double MovingBall::min_stretch(const Vec3& p) const {
  double q = std::numeric_limits<double>::infinity();
  for (const Opposite& o : opposite_) q = std::min(q, stretch(o, p));
  return q;
}

bool MovingBall::exceeds(const Vec3& p, double bound, double* min) {
  const std::size_t n = opposite_.size();
  double q = std::numeric_limits<double>::infinity();
  std::size_t lowest = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = order_[k];
    const double s = stretch(opposite_[i], p);
    if (!(s > bound)) {
      // Tried first next time.
      std::rotate(order_.begin(), order_.begin() + static_cast<std::ptrdiff_t>(k),
                  order_.begin() + static_cast<std::ptrdiff_t>(k) + 1);
      return false;
    }
    if (s < q) {
      q = s;
      lowest = k;
    }
  }
  // The lowest tet at the new position in front.
  std::rotate(order_.begin(), order_.begin() + static_cast<std::ptrdiff_t>(lowest),
              order_.begin() + static_cast<std::ptrdiff_t>(lowest) + 1);
  *min = q;
  return true;
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
