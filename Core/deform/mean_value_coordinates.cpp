// Mean value coordinates (thesis 2.5.4.4): Floater 2003 on a surface's
// triangle fan (Eqs. 2.11-2.12) and Ju et al. 2005 inside a closed triangle
// mesh (Eqs. 2.13-2.20).
#include "deform/deform.h"

#include <algorithm>
#include <cmath>

namespace femorph {

void mean_value_coordinates_2d(const Vec3& x, const std::vector<Vec3>& vertices,
                               const std::vector<std::array<int, 2>>& fan, std::vector<double>& weights) {
  weights.assign(vertices.size(), 0.0);
  // Eq. 2.11 summed per triangle: the triangle (x, a, b) with angle alpha at
  // x adds tan(alpha / 2) / |x_a - x| to a and tan(alpha / 2) / |x_b - x| to b.
  for (const auto& ab : fan) {
    const Vec3 u = vertices[ab[0]] - x, v = vertices[ab[1]] - x;
    const double lu = u.norm(), lv = v.norm();
    if (!(lu > 0) || !(lv > 0)) continue;
    const double alpha = std::atan2(u.cross(v).norm(), u.dot(v));
    const double t = std::tan(0.5 * alpha);
    weights[ab[0]] += t / lu;
    weights[ab[1]] += t / lv;
  }
  double sum = 0;
  for (double w : weights) sum += w;
  if (sum > 0) {
    for (double& w : weights) w /= sum;  // Eq. 2.12
  } else if (!weights.empty()) {
    std::fill(weights.begin(), weights.end(), 1.0 / weights.size());
  }
}

bool mean_value_coordinates_3d(const Vec3& x, const std::vector<Vec3>& vertices, const std::vector<Tri>& triangles,
                               std::vector<double>& weights) {
  const std::size_t n = vertices.size();
  weights.assign(n, 0.0);
  thread_local std::vector<Vec3> u;
  thread_local std::vector<double> d;
  u.resize(n);
  d.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3 r = vertices[j] - x;
    d[j] = r.norm();
    if (d[j] < 1e-300) {  // x is a vertex
      weights[j] = 1;
      return false;
    }
    u[j] = r / d[j];
  }
  constexpr double eps = 1e-12;
  for (const Tri& tri : triangles) {
    const int i[3] = {static_cast<int>(tri[0]), static_cast<int>(tri[1]), static_cast<int>(tri[2])};
    double theta[3], sin_theta[3], half_chord[3], c[3], s[3];
    double h = 0;
    for (int k = 0; k < 3; ++k) {
      // Arc lengths L^s of the spherical triangle (Eq. 2.18's terms): the
      // chord l of the arc theta is 2 sin(theta / 2), so sin(theta) =
      // l sqrt(1 - l^2 / 4) needs no more trigonometry.
      const double half = std::min(1.0, 0.5 * (u[i[(k + 1) % 3]] - u[i[(k + 2) % 3]]).norm());
      half_chord[k] = half;
      theta[k] = 2 * std::asin(half);
      sin_theta[k] = 2 * half * std::sqrt(std::max(0.0, 1 - half * half));
      h += 0.5 * theta[k];
    }
    if (kPi - h < eps) {
      // x lies on this triangle: barycentric coordinates.
      double b[3], sum = 0;
      for (int k = 0; k < 3; ++k) {
        b[k] = sin_theta[k] * d[i[(k + 2) % 3]] * d[i[(k + 1) % 3]];
        sum += b[k];
      }
      std::fill(weights.begin(), weights.end(), 0.0);
      for (int k = 0; k < 3; ++k) weights[i[k]] = sum > 0 ? b[k] / sum : 1.0 / 3;
      return false;
    }
    const double det = u[i[0]].dot(u[i[1]].cross(u[i[2]]));
    const double sign = det < 0 ? -1.0 : 1.0;
    bool skip = false;
    const double sin_h = std::sin(h), cos_h = std::cos(h);
    for (int k = 0; k < 3; ++k) {
      // Eq. 2.17: the angles of the spherical triangle; sin(h - theta) by
      // the difference formula, with cos(theta) = 1 - l^2 / 2.
      const double denom = sin_theta[(k + 1) % 3] * sin_theta[(k + 2) % 3];
      const double cos_theta = 1 - 2 * half_chord[k] * half_chord[k];
      const double sin_h_theta = sin_h * cos_theta - cos_h * sin_theta[k];
      c[k] = denom > 0 ? 2 * sin_h * sin_h_theta / denom - 1 : 1;
      c[k] = std::clamp(c[k], -1.0, 1.0);
      s[k] = sign * std::sqrt(std::max(0.0, 1 - c[k] * c[k]));
      if (std::abs(s[k]) <= eps) skip = true;  // x in the triangle's plane, outside it
    }
    if (skip) continue;
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      // Eq. 2.16.
      weights[i[k]] += (theta[k] - c[k1] * theta[k2] - c[k2] * theta[k1]) /
                       (d[i[k]] * sin_theta[k1] * s[k2]);
    }
  }
  double sum = 0;
  for (double w : weights) sum += w;
  if (std::abs(sum) > 0) {
    for (double& w : weights) w /= sum;  // Eq. 2.20
  }
  return true;
}

void vertex_ring_mvc(const TetMesh& mesh, index_t v, std::vector<index_t>& ids, std::vector<double>& weights) {
  thread_local std::vector<index_t> ball;
  thread_local std::vector<Vec3> ring;
  thread_local std::vector<Tri> link;
  thread_local TetMesh::WalkMarks marks;  // callers may run in parallel
  mesh.vertex_ball(v, ball, marks);
  ids.clear();
  ring.clear();
  link.clear();
  const auto local = [&](index_t id) {
    const auto it = std::find(ids.begin(), ids.end(), id);
    if (it != ids.end()) return static_cast<index_t>(it - ids.begin());
    ids.push_back(id);
    ring.push_back(mesh.point(id));
    return static_cast<index_t>(ids.size() - 1);
  };
  for (const index_t t : ball) {
    const int i = mesh.local_index(t, v);
    const Tet& T = mesh.tet(t);
    link.push_back({local(T[kTetFace[i][0]]), local(T[kTetFace[i][1]]), local(T[kTetFace[i][2]])});
  }
  mean_value_coordinates_3d(mesh.point(v), ring, link, weights);
}

}  // namespace femorph
