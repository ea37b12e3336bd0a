#include "geometry/fit_primitives.h"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>

namespace femorph {

Circle2dFit fit_circle_2d(const std::vector<Eigen::Vector2d>& points) {
  using Eigen::Vector2d;
  Circle2dFit fit;
  const int n = static_cast<int>(points.size());
  if (n < 3) return fit;
  // Centre and scale first: the algebraic system is then well conditioned
  // whatever the units and the distance from the origin.
  Vector2d mean = Vector2d::Zero();
  for (const Vector2d& p : points) mean += p;
  mean /= n;
  double scale = 0;
  for (const Vector2d& p : points) scale += (p - mean).squaredNorm();
  scale = std::sqrt(scale / n);
  if (!(scale > 0)) return fit;
  std::vector<Vector2d> z(n);
  for (int i = 0; i < n; ++i) z[i] = (points[i] - mean) / scale;

  // Kasa: x^2 + y^2 + D x + E y + F = 0 by linear least squares.
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    A.row(i) << z[i].x(), z[i].y(), 1.0;
    b(i) = -z[i].squaredNorm();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3) return fit;
  const Eigen::Vector3d def = qr.solve(b);
  Vector2d c(-0.5 * def(0), -0.5 * def(1));
  const double r2 = c.squaredNorm() - def(2);
  if (!(r2 > 0)) return fit;
  double r = std::sqrt(r2);
  // Collinear points: the circle runs off to infinity.
  if (!(r < 1e8)) return fit;

  // Gauss-Newton on the geometric distances |z - c| - r (3 unknowns), each
  // step halved until the cost decreases.
  const auto cost_of = [&](const Vector2d& cc, double rr) {
    double s = 0;
    for (const Vector2d& p : z) s += std::pow((p - cc).norm() - rr, 2);
    return s;
  };
  double cost = cost_of(c, r);
  for (int iteration = 0; iteration < 50 && cost > 0; ++iteration) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const Vector2d& p : z) {
      const Vector2d d = p - c;
      const double len = d.norm();
      if (!(len > 0)) continue;
      const Eigen::Vector3d j(-d.x() / len, -d.y() / len, -1.0);
      H += j * j.transpose();
      g += j * (len - r);
    }
    const Eigen::Vector3d step = -H.ldlt().solve(g);
    if (!step.allFinite()) break;
    double factor = 1;
    bool improved = false;
    for (int halving = 0; halving < 30; ++halving, factor *= 0.5) {
      const Vector2d c_new = c + factor * step.head<2>();
      const double r_new = r + factor * step(2);
      const double cost_new = cost_of(c_new, r_new);
      if (cost_new < cost) {
        c = c_new;
        r = r_new;
        improved = (cost - cost_new) > 1e-15 * cost && step.norm() * factor > 1e-15;
        cost = cost_new;
        break;
      }
    }
    if (!improved) break;
  }

  fit.center = mean + scale * c;
  fit.radius = scale * std::abs(r);
  double sum = 0, largest = 0;
  for (const Vector2d& p : points) {
    const double d = (p - fit.center).norm() - fit.radius;
    sum += d * d;
    largest = std::max(largest, std::abs(d));
  }
  fit.rms = std::sqrt(sum / n);
  fit.max_abs = largest;
  fit.ok = std::isfinite(fit.rms) && fit.radius > 0;
  return fit;
}

}  // namespace femorph
