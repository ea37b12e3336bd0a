#include "segment/normal_tensor_curvature.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

namespace femorph {
namespace {

// The height fit of the normal refinement has five unknowns.
constexpr int kFitUnknowns = 5;
// Smallest / largest pivot of a normalised least-squares system below which
// the neighbourhood does not determine the unknowns.
constexpr double kMinPivotRatio = 1e-9;
// A refinement that tilts the normal tensor's e1 by more than this (slope
// 0.5, about 27 deg) is not trusted: the 1-ring is then not a graph over the
// tangent plane.
constexpr double kMaxRefinementSlope = 0.5;

// Calls fn(j) once for every vertex j joined to v by an edge. Around a vertex
// of a closed surface each neighbour is the successor of v in exactly one
// triangle; at an open edge the predecessor is added.
template <class Fn>
inline void for_each_neighbour(const SurfaceMesh& s, index_t v, Fn&& fn) {
  for (index_t q = s.vertex_offsets[v]; q < s.vertex_offsets[v + 1]; ++q) {
    const index_t f = s.vertex_triangles[q];
    const Tri& t = s.triangles[f];
    const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    fn(t[(k + 1) % 3]);
    if (s.neighbors[f][(k + 2) % 3] < 0) fn(t[(k + 2) % 3]);
  }
}

// A unit vector orthogonal to n, close to `hint` when it is not parallel.
inline Vec3 tangent_towards(const Vec3& n, const Vec3& hint) {
  Vec3 t = hint - hint.dot(n) * n;
  if (t.squaredNorm() < 1e-12) t = n.unitOrthogonal();
  return t.normalized();
}

// Local height fit of a vertex: h = p u + q w + a u^2/2 + b u w + c w^2/2 in
// the frame (f1, f2 = n0 x f1, n0), n0 the normal tensor's e1.
struct HeightFit {
  Vec3 n0 = Vec3::Zero(), f1 = Vec3::Zero();
  std::array<double, kFitUnknowns> coef{};
  bool ok = false;

  // Unit normal of the fitted graph above the point x (relative to the vertex).
  Vec3 normal_at(const Vec3& d) const {
    const Vec3 f2 = n0.cross(f1);
    const double u = d.dot(f1), w = d.dot(f2);
    const double hu = coef[0] + coef[2] * u + coef[3] * w;
    const double hw = coef[1] + coef[3] * u + coef[4] * w;
    return (n0 - hu * f1 - hw * f2).normalized();
  }
};

using Mat7 = Eigen::Matrix<double, 7, 7>;
using Vec7 = Eigen::Matrix<double, 7, 1>;
inline bool env_flag(const char* name, bool dflt) { const char* v = std::getenv(name); return v ? v[0] == '1' : dflt; }
inline bool use_positions() { static bool b = env_flag("CURV_POS", true); return b; }
inline bool slope_form() { static bool b = env_flag("CURV_SLOPE", true); return b; }
inline int min_ring() { static int b = std::getenv("CURV_RING") ? atoi(std::getenv("CURV_RING")) : 6; return b; }
inline int min_second() { static int b = std::getenv("CURV_MINSEC") ? atoi(std::getenv("CURV_MINSEC")) : 6; return b; }
inline bool second_order() { static bool b = env_flag("CURV_SECOND", true); return b; }

// Sign convention for unsigned directions: the largest component positive,
// so that neighbouring vertices agree wherever the direction is stable.
inline Vec3 canonical_sign(const Vec3& d) {
  int k;
  d.cwiseAbs().maxCoeff(&k);
  return d[k] < 0 ? Vec3(-d) : d;
}

}  // namespace

// Thesis 2.4.2 (A12). Per vertex off the sharp edges:
//  1. Eq. 2.1, the normal tensor N_i = sum n_t n_t^T over the triangles around
//     i; its eigenvectors e1 (normal, oriented like the area-weighted mean of
//     the triangle normals), e2, e3.
//  2. (Not in the thesis.) e1 is refined by a least-squares height fit of the
//     1-ring over the plane of (e2, e3): the vertices lie on the CAD surface,
//     so the fitted slope gives a normal exact to second order, whereas the
//     tensor's e1 of an irregular 1-ring is off by O(h). Eq. 2.3 divides
//     normal differences by edge lengths, so those errors would become O(1)
//     curvature errors and wrong principal directions.
//  3. Eqs. 2.2-2.3: the shape operator in the tangent frame (e2, e3) from the
//     neighbours' normal differences a_Ro = n_j - n_i against their tangent
//     offsets a_Gr. Written in that 2D frame, A_Gr A_Gr^T is the invertible
//     2x2 block of the 3x3 matrix that Eqs. 2.4-2.5 make invertible by
//     appending (n_i, 0). The operator is solved as a symmetric 2x2 (three
//     unknowns by least squares), not symmetrised afterwards.
//     Neighbours on sharp edges have no normal of their own (their tensor
//     mixes two surfaces): the normal of i's height fit above them stands in.
//  4. k_max, k_min (by magnitude) and their directions from the 2x2 eigen
//     decomposition. Signs: n outward, so dn/dx > 0 where convex.
// Per triangle: the mean over its valid vertices.
Curvature normal_tensor_curvature(const SurfaceMesh& surface, const SharpEdges& sharp) {
  const index_t np = surface.num_points();
  const index_t nf = surface.num_triangles();
  const std::vector<Vec3>& x = surface.points;
  Curvature c;
  c.vertex_valid.assign(np, 0);
  c.vertex_normal.assign(np, Vec3::Zero());
  c.vertex_k_max.assign(np, 0.0);
  c.vertex_k_min.assign(np, 0.0);
  c.vertex_dir_max.assign(np, Vec3::Zero());
  c.vertex_dir_min.assign(np, Vec3::Zero());
  std::vector<HeightFit> fits(np);
  // Vertices whose normal tensor was evaluated (steps 1-2); read by every
  // neighbour in steps 3-4, so kept apart from the final vertex_valid.
  std::vector<char> evaluated(np, 0);

  // Steps 1-2: normal tensor, e1, refined normal.
#pragma omp parallel
  {
  std::vector<index_t> ring;  // the fit's neighbourhood
  ring.reserve(64);
#pragma omp for schedule(dynamic, 1024)
  for (index_t i = 0; i < np; ++i) {
    Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
    Vec3 mean_normal = Vec3::Zero();
    for (index_t q = surface.vertex_offsets[i]; q < surface.vertex_offsets[i + 1]; ++q) {
      const index_t f = surface.vertex_triangles[q];
      const Vec3& n = surface.normals[f];
      tensor.noalias() += n * n.transpose();  // Eq. 2.1
      mean_normal += surface.areas[f] * n;
    }
    if (mean_normal.squaredNorm() == 0) continue;  // no triangle with a normal
    mean_normal.normalize();
    c.vertex_normal[i] = mean_normal;
    if (sharp.vertex_degree[i] != 0) continue;  // not evaluated (thesis 2.4.2)

    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(tensor);
    Vec3 e1 = eig.eigenvectors().col(2);  // eigenvalues ascending
    if (e1.dot(mean_normal) < 0) e1 = -e1;
    HeightFit& fit = fits[i];
    fit.n0 = e1;
    fit.f1 = tangent_towards(e1, eig.eigenvectors().col(1));  // e2
    const Vec3 f2 = e1.cross(fit.f1);

    // Height fit over the 1-ring; over the 2-ring when the 1-ring has fewer
    // vertices than unknowns (grown only through vertices off sharp edges, so
    // that it stays on i's surface). Lengths scaled by the mean distance.
    ring.clear();
    for_each_neighbour(surface, i, [&](index_t j) { ring.push_back(j); });
    if (ring.size() < static_cast<std::size_t>(min_ring())) {
      const std::size_t one_ring = ring.size();
      for (std::size_t q = 0; q < one_ring; ++q) {
        if (sharp.vertex_degree[ring[q]] != 0) continue;
        for_each_neighbour(surface, ring[q], [&](index_t k) {
          if (k != i && std::find(ring.begin(), ring.end(), k) == ring.end()) ring.push_back(k);
        });
      }
    }
    double length_sum = 0;
    for (index_t j : ring) length_sum += (x[j] - x[i]).norm();
    Vec3 n = e1;
    if (ring.size() >= static_cast<std::size_t>(kFitUnknowns) && length_sum > 0) {
      const double scale = static_cast<double>(ring.size()) / length_sum;
      Eigen::Matrix<double, kFitUnknowns, kFitUnknowns> m = Eigen::Matrix<double, kFitUnknowns, kFitUnknowns>::Zero();
      Eigen::Matrix<double, kFitUnknowns, 1> rhs = Eigen::Matrix<double, kFitUnknowns, 1>::Zero();
      for (index_t j : ring) {
        const Vec3 d = (x[j] - x[i]) * scale;
        const double u = d.dot(fit.f1), w = d.dot(f2), h = d.dot(e1);
        Eigen::Matrix<double, kFitUnknowns, 1> row;
        row << u, w, 0.5 * u * u, u * w, 0.5 * w * w;
        m.selfadjointView<Eigen::Lower>().rankUpdate(row);
        rhs += h * row;
      }
      m.triangularView<Eigen::StrictlyUpper>() = m.transpose();
      const Eigen::LDLT<Eigen::Matrix<double, kFitUnknowns, kFitUnknowns>> ldlt(m);
      const auto pivots = ldlt.vectorD().cwiseAbs();
      if (ldlt.info() == Eigen::Success && pivots.minCoeff() > kMinPivotRatio * pivots.maxCoeff()) {
        const Eigen::Matrix<double, kFitUnknowns, 1> s = ldlt.solve(rhs);
        if (std::hypot(s[0], s[1]) < kMaxRefinementSlope) {
          for (int k = 0; k < kFitUnknowns; ++k) fit.coef[k] = s[k];
          // Back to unscaled lengths: slopes unchanged, second derivatives * scale.
          for (int k = 2; k < kFitUnknowns; ++k) fit.coef[k] *= scale;
          fit.ok = true;
          n = (e1 - s[0] * fit.f1 - s[1] * f2).normalized();
        }
      }
    }
    c.vertex_normal[i] = n;
    evaluated[i] = 1;
  }
  }

  // Steps 3-4: Eqs. 2.2-2.3 in the tangent frame of the refined normal.
#pragma omp parallel for schedule(dynamic, 1024)
  for (index_t i = 0; i < np; ++i) {
    if (!evaluated[i]) continue;
    const Vec3& n = c.vertex_normal[i];
    const HeightFit& fit = fits[i];
    const Vec3 t1 = tangent_towards(n, fit.f1), t2 = n.cross(t1);
    // Least squares over the 1-ring for theta = (a, b, c, D, E, F, G):
    //   normals    r_j = S g_j + grad C(g_j)          (2 rows, Eq. 2.3 + 2nd order)
    //   positions -z_j = g_j^T S g_j / 2 + C(g_j)      (1 row, divided by |g_j|)
    // S = [a b; b c], C(u, w) = (D u^3 + 3E u^2 w + 3F u w^2 + G w^3) / 6,
    // g_j = a_Gr in (t1, t2), r_j = a_Ro in (t1, t2), z_j = a_Dis . n_i.
    // Lengths scaled by the 1-ring's mean distance.
    double length_sum = 0;
    int count = 0;
    for_each_neighbour(surface, i, [&](index_t j) {
      length_sum += (x[j] - x[i]).norm();
      ++count;
    });
    if (!count || length_sum <= 0) continue;
    const double scale = count / length_sum;
    int with_normal = 0;
    Mat7 m = Mat7::Zero();
    Vec7 rhs = Vec7::Zero();
    for_each_neighbour(surface, i, [&](index_t j) {
      const Vec3 d = (x[j] - x[i]) * scale;
      const double u = d.dot(t1), w = d.dot(t2), z = d.dot(n);
      const double rho = std::hypot(u, w);
      if (rho == 0) return;
      Vec7 row;
      if (use_positions()) {
        row << 0.5 * u * u, u * w, 0.5 * w * w, u * u * u / 6, 0.5 * u * u * w, 0.5 * u * w * w, w * w * w / 6;
        row /= rho;
        m.selfadjointView<Eigen::Lower>().rankUpdate(row);
        rhs -= (z / rho) * row;
      }
      if (!evaluated[j]) return;  // on a sharp edge: its normal mixes two surfaces
      const Vec3& nj = c.vertex_normal[j];
      ++with_normal;
      double r1 = (nj - n).dot(t1), r2 = (nj - n).dot(t2);  // a_Ro
      if (slope_form()) {
        const double nz = nj.dot(n);
        if (nz <= 0) return;
        r1 /= nz;
        r2 /= nz;
      }
      row << u, w, 0, 0.5 * u * u, u * w, 0.5 * w * w, 0;
      m.selfadjointView<Eigen::Lower>().rankUpdate(row);
      rhs += r1 * row;
      row << 0, u, w, 0, 0.5 * u * u, u * w, 0.5 * w * w;
      m.selfadjointView<Eigen::Lower>().rankUpdate(row);
      rhs += r2 * row;
    });
    m.triangularView<Eigen::StrictlyUpper>() = m.transpose();
    Vec3 s;
    int unknowns = second_order() && with_normal >= min_second() ? 7 : 3;
    bool solved = false;
    for (; unknowns >= 3 && !solved; unknowns -= 4) {
      const Eigen::MatrixXd sub = m.topLeftCorner(unknowns, unknowns);
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(sub);
      const auto pivots = ldlt.vectorD().cwiseAbs();
      if (ldlt.info() != Eigen::Success || !(pivots.maxCoeff() > 0) ||
          pivots.minCoeff() < kMinPivotRatio * pivots.maxCoeff())
        continue;
      const Eigen::VectorXd sol = ldlt.solve(rhs.head(unknowns));
      s = sol.head<3>() * scale;
      solved = true;
    }
    if (!solved) continue;  // tangent offsets collinear: operator undetermined
    const double a = s[0], b = s[1], cc = s[2];
    // Eigen decomposition of [a b; b cc]: lambda_+ along angle phi.
    const double mean = 0.5 * (a + cc), radius = std::hypot(0.5 * (a - cc), b);
    const double phi = 0.5 * std::atan2(2 * b, a - cc);
    const Vec3 dir_plus = std::cos(phi) * t1 + std::sin(phi) * t2;
    const double k_plus = mean + radius, k_minus = mean - radius;
    Vec3 dir_min;
    if (std::abs(k_plus) >= std::abs(k_minus)) {
      c.vertex_k_max[i] = k_plus;
      c.vertex_k_min[i] = k_minus;
      dir_min = n.cross(dir_plus);
    } else {
      c.vertex_k_max[i] = k_minus;
      c.vertex_k_min[i] = k_plus;
      dir_min = dir_plus;
    }
    dir_min = canonical_sign(dir_min);
    c.vertex_dir_min[i] = dir_min;
    c.vertex_dir_max[i] = dir_min.cross(n);  // (dir_max, dir_min, n) right-handed
    c.vertex_valid[i] = 1;
  }

  // Per triangle: mean over the valid vertices, directions aligned with the
  // first valid vertex's.
  c.triangle_valid.assign(nf, 0);
  c.triangle_k_max.assign(nf, 0.0);
  c.triangle_k_min.assign(nf, 0.0);
  c.triangle_dir_max.assign(nf, Vec3::Zero());
  c.triangle_dir_min.assign(nf, Vec3::Zero());
#pragma omp parallel for schedule(static)
  for (index_t f = 0; f < nf; ++f) {
    int count = 0;
    double k_max = 0, k_min = 0;
    Vec3 dir_max = Vec3::Zero(), dir_min = Vec3::Zero();
    for (index_t v : surface.triangles[f]) {
      if (!c.vertex_valid[v]) continue;
      k_max += c.vertex_k_max[v];
      k_min += c.vertex_k_min[v];
      const Vec3& dmax = c.vertex_dir_max[v];
      const Vec3& dmin = c.vertex_dir_min[v];
      dir_max += count && dmax.dot(dir_max) < 0 ? Vec3(-dmax) : dmax;
      dir_min += count && dmin.dot(dir_min) < 0 ? Vec3(-dmin) : dmin;
      ++count;
    }
    if (!count) continue;
    c.triangle_valid[f] = 1;
    c.triangle_k_max[f] = k_max / count;
    c.triangle_k_min[f] = k_min / count;
    if (dir_max.squaredNorm() > 0) c.triangle_dir_max[f] = canonical_sign(dir_max.normalized());
    if (dir_min.squaredNorm() > 0) c.triangle_dir_min[f] = canonical_sign(dir_min.normalized());
  }
  return c;
}

}  // namespace femorph
