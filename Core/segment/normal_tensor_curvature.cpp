#include "segment/normal_tensor_curvature.h"
#include "common/parallel.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace femorph {
namespace {

// Smallest / largest pivot of a least-squares system (lengths normalised by
// the local edge length) below which the neighbourhood does not determine
// the unknowns: a smaller one amplifies the data's errors a hundredfold. (On
// fandisk, a valence-4 vertex whose neighbours form a symmetric cross gets
// curvatures of 1e4 / edge length from the position rows otherwise.)
constexpr double kMinPivotRatio = 1e-4;
// A refinement that tilts the normal tensor's e1 by more than this slope
// (about 27 deg) is not trusted: the neighbourhood is not a graph over the
// tangent plane.
constexpr double kMaxRefinementSlope = 0.5;
// The quadratic normal fit (5 unknowns) uses the 1-ring when it has at least
// this many vertices; a smaller one is interpolated exactly, and near-
// singular configurations then tilt the normal by degrees. Smaller 1-rings
// use the 2-ring with a cubic fit (9 unknowns) when it has enough vertices.
constexpr std::size_t kMinOneRing = 6;
constexpr std::size_t kMinCubicPoints = 12;

template <int N>
using Mat = Eigen::Matrix<double, N, N>;
template <int N>
using Vec = Eigen::Matrix<double, N, 1>;

// m += r r^T on the lower triangle, all that LDLT reads.
template <int N>
inline void add_outer_lower(Mat<N>& m, const Vec<N>& r) {
  for (int a = 0; a < N; ++a)
    for (int b = 0; b <= a; ++b) m(a, b) += r[a] * r[b];
}

// Solves the normal equations m x = rhs (m symmetric, lower triangle used);
// false when m is singular or too badly conditioned.
template <int N>
bool solve_least_squares(const Mat<N>& m, const Vec<N>& rhs, Vec<N>& x) {
  const Eigen::LDLT<Mat<N>> ldlt(m);
  const Vec<N> pivots = ldlt.vectorD().cwiseAbs();
  if (ldlt.info() != Eigen::Success || !(pivots.maxCoeff() > 0) ||
      pivots.minCoeff() < kMinPivotRatio * pivots.maxCoeff())
    return false;
  x = ldlt.solve(rhs);
  return true;
}

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

// Least-squares height function h(u, w) through the vertex at `origin` over
// the points `ring`, in the frame (f1, f2, n0): slopes p, q, then the
// quadratic terms, then (N = 9) the cubic ones. Returns the slopes.
template <int N>
bool fit_slopes(const std::vector<Vec3>& x, const std::vector<index_t>& ring, const Vec3& origin, const Vec3& f1,
                const Vec3& f2, const Vec3& n0, double& p, double& q) {
  double length_sum = 0;
  for (index_t j : ring) length_sum += (x[j] - origin).norm();
  if (!(length_sum > 0)) return false;
  const double scale = static_cast<double>(ring.size()) / length_sum;  // slopes are scale-free
  Mat<N> m = Mat<N>::Zero();
  Vec<N> rhs = Vec<N>::Zero();
  for (index_t j : ring) {
    const Vec3 d = (x[j] - origin) * scale;
    const double u = d.dot(f1), w = d.dot(f2);
    Vec<N> row;
    row.template head<5>() << u, w, 0.5 * u * u, u * w, 0.5 * w * w;
    if constexpr (N == 9) row.template tail<4>() << u * u * u, u * u * w, u * w * w, w * w * w;
    add_outer_lower(m, row);
    rhs += d.dot(n0) * row;
  }
  Vec<N> s;
  if (!solve_least_squares<N>(m, rhs, s)) return false;
  p = s[0];
  q = s[1];
  return std::hypot(p, q) < kMaxRefinementSlope;
}

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
//  2. (Added.) e1 is refined by a least-squares height fit over (e2, e3) of
//     the 1-ring (quadratic; the 2-ring and a cubic when the 1-ring has fewer
//     than 6 vertices). The vertices lie on the CAD surface, so the fitted
//     slope is exact to second order, whereas the tensor's e1 of an irregular
//     1-ring is off by O(h): Eq. 2.3 divides normal differences by edge
//     lengths, so that error would become an O(1) error of the curvatures
//     and degrees of error in the principal directions.
//  3. Eqs. 2.2-2.3: the shape operator S in the tangent frame (e2, e3), by
//     least squares from the neighbours' a_Ro = n_j - n_i against their
//     a_Gr (both written in the frame). In 2D, A_Gr A_Gr^T is the invertible
//     2x2 block of the 3x3 matrix that Eqs. 2.4-2.5 make invertible by
//     appending (n_i, 0). S is solved as a symmetric matrix (three
//     unknowns), not symmetrised afterwards. (Added.) The linear model
//     a_Ro = S a_Gr has an O(h) error where the curvature varies (cones,
//     tori); a second-order term, the gradient of a cubic form C (four more
//     unknowns), removes it, and the neighbours' heights above the tangent
//     plane, -a_Dis.n_i = a_Gr^T S a_Gr / 2 + C(a_Gr), add one row each. A
//     neighbour on a sharp edge has no normal (its tensor mixes two surfaces:
//     thesis 2.4.2), so it gives only its height row: it lies on i's surface.
//     Too few rows for seven unknowns: S alone (the thesis's linear model).
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
  // Steps 1-2 give every evaluated vertex its normal and the tensor's e2,
  // which orients the tangent frame of step 3. `evaluated` is read by every
  // neighbour in step 3, so it is kept apart from the final vertex_valid.
  std::vector<Vec3> frame_e2(np, Vec3::Zero());
  std::vector<char> evaluated(np, 0);

  // Steps 1-2: normal tensor, e1, refined normal.
  parallel_for_chunks(
      np,
      [&](long begin, long end, int) {
        std::vector<index_t> ring;
        ring.reserve(64);
        for (index_t i = static_cast<index_t>(begin); i < static_cast<index_t>(end); ++i) {
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
          c.vertex_normal[i] = mean_normal;           // what unevaluated vertices keep
          if (sharp.vertex_degree[i] != 0) continue;  // not evaluated (thesis 2.4.2)

          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
          eig.computeDirect(tensor);
          Vec3 e1 = eig.eigenvectors().col(2);  // eigenvalues ascending
          if (e1.dot(mean_normal) < 0) e1 = -e1;
          const Vec3 f1 = tangent_towards(e1, eig.eigenvectors().col(1));  // e2
          const Vec3 f2 = e1.cross(f1);

          ring.clear();
          for_each_neighbour(surface, i, [&](index_t j) { ring.push_back(j); });
          const bool two_ring = ring.size() < kMinOneRing;
          if (two_ring) {
            // Grown only through vertices off sharp edges: it stays on i's surface.
            const std::size_t one_ring = ring.size();
            for (std::size_t q = 0; q < one_ring; ++q) {
              if (sharp.vertex_degree[ring[q]] != 0) continue;
              for_each_neighbour(surface, ring[q], [&](index_t k) {
                if (k != i && std::find(ring.begin(), ring.end(), k) == ring.end()) ring.push_back(k);
              });
            }
          }
          double p = 0, q = 0;
          bool fitted = false;
          if (two_ring && ring.size() >= kMinCubicPoints) fitted = fit_slopes<9>(x, ring, x[i], f1, f2, e1, p, q);
          if (!fitted && ring.size() >= 5) fitted = fit_slopes<5>(x, ring, x[i], f1, f2, e1, p, q);
          c.vertex_normal[i] = fitted ? Vec3((e1 - p * f1 - q * f2).normalized()) : e1;
          frame_e2[i] = f1;
          evaluated[i] = 1;
        }
      },
      kParallelMinHeavyItems, 256);

  // Steps 3-4: Eqs. 2.2-2.3 in the tangent frame of the refined normal.
  // Unknowns (a, b, c, D, E, F, G): S = [a b; b c] and
  // C(u, w) = (D u^3 + 3E u^2 w + 3F u w^2 + G w^3) / 6. Rows per neighbour j,
  // with g = a_Gr, r = a_Ro in the frame and z = a_Dis . n_i:
  //   r = S g + grad C(g)                   (unless j is on a sharp edge)
  //   -z / |g| = (g^T S g / 2 + C(g)) / |g|  (divided by |g| to weigh like r)
  // Lengths scaled by the 1-ring's mean edge length.
  parallel_for_chunks(
      static_cast<long>(np),
      [&](long begin, long end, int) {
        for (index_t i = static_cast<index_t>(begin); i < static_cast<index_t>(end); ++i) {
          if (!evaluated[i]) continue;
          const Vec3& n = c.vertex_normal[i];
          const Vec3 t1 = tangent_towards(n, frame_e2[i]), t2 = n.cross(t1);
          double length_sum = 0;
          int count = 0;
          for_each_neighbour(surface, i, [&](index_t j) {
            length_sum += (x[j] - x[i]).norm();
            ++count;
          });
          if (!(length_sum > 0)) continue;
          const double scale = count / length_sum;
          Mat<7> m = Mat<7>::Zero();
          Vec<7> rhs = Vec<7>::Zero();
          Vec<7> row;
          for_each_neighbour(surface, i, [&](index_t j) {
            const Vec3 d = (x[j] - x[i]) * scale;
            const double u = d.dot(t1), w = d.dot(t2), z = d.dot(n);
            const double rho = std::sqrt(u * u + w * w);
            if (rho == 0) return;
            row << 0.5 * u * u, u * w, 0.5 * w * w, u * u * u / 6, 0.5 * u * u * w, 0.5 * u * w * w, w * w * w / 6;
            row /= rho;
            add_outer_lower(m, row);
            rhs -= (z / rho) * row;
            if (!evaluated[j]) return;
            const Vec3 ro = c.vertex_normal[j] - n;  // a_Ro
            const double r1 = ro.dot(t1), r2 = ro.dot(t2);
            row << u, w, 0, 0.5 * u * u, u * w, 0.5 * w * w, 0;
            add_outer_lower(m, row);
            rhs += r1 * row;
            row << 0, u, w, 0, 0.5 * u * u, u * w, 0.5 * w * w;
            add_outer_lower(m, row);
            rhs += r2 * row;
          });
          Vec3 s;
          Vec<7> full;
          if (solve_least_squares<7>(m, rhs, full)) {
            s = full.head<3>();
          } else if (!solve_least_squares<3>(m.topLeftCorner<3, 3>(), rhs.head<3>(), s)) {
            continue;  // tangent offsets collinear: the operator is undetermined
          }
          s *= scale;  // back to unscaled lengths
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
      },
      kParallelMinHeavyItems, 256);

  // Per triangle: mean over the valid vertices, directions aligned with the
  // first valid vertex's.
  c.triangle_valid.assign(nf, 0);
  c.triangle_k_max.assign(nf, 0.0);
  c.triangle_k_min.assign(nf, 0.0);
  c.triangle_dir_max.assign(nf, Vec3::Zero());
  c.triangle_dir_min.assign(nf, Vec3::Zero());
  parallel_for_chunks(
      static_cast<long>(nf),
      [&](long begin, long end, int) {
        for (index_t f = static_cast<index_t>(begin); f < static_cast<index_t>(end); ++f) {
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
      },
      kParallelMinItems);
  return c;
}

}  // namespace femorph
