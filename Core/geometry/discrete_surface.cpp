#include "geometry/discrete_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace femorph {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Barycentric regions of the triangle's plane: a vertex, an edge or the
  // inside. The edge tests come last so that degenerate triangles fall on
  // the best of their edges.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  const double denominator = va + vb + vc;
  if (va > 0 && vb > 0 && vc > 0 && denominator > 0) return a + (vb / denominator) * ab + (vc / denominator) * ac;
  // On an edge: the closest of the three segments.
  const auto on_segment = [&p](const Vec3& s, const Vec3& e) {
    const Vec3 d = e - s;
    const double l2 = d.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - s).dot(d) / l2, 0.0, 1.0) : 0.0;
    return Vec3(s + t * d);
  };
  Vec3 best = on_segment(a, b);
  for (const Vec3& q : {on_segment(b, c), on_segment(c, a)})
    if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
  return best;
}

std::array<int, 3> DiscreteSurface::cell_of(const Vec3& p) const {
  std::array<int, 3> c;
  for (int i = 0; i < 3; ++i) {
    const double x = std::floor((p[i] - origin_[i]) / cell_);
    c[i] = static_cast<int>(std::clamp(x, 0.0, static_cast<double>(dims_[i] - 1)));
  }
  return c;
}

void DiscreteSurface::build(std::vector<std::array<Vec3, 3>> triangles) {
  triangles_ = std::move(triangles);
  cell_start_.clear();
  cell_items_.clear();
  if (triangles_.empty()) return;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double extent = 0;
  for (const auto& t : triangles_) {
    Vec3 tlo = t[0], thi = t[0];
    for (const Vec3& q : t) {
      tlo = tlo.cwiseMin(q);
      thi = thi.cwiseMax(q);
    }
    lo = lo.cwiseMin(tlo);
    hi = hi.cwiseMax(thi);
    extent += (thi - tlo).maxCoeff();
  }
  extent /= static_cast<double>(triangles_.size());
  // A cell about as wide as the mean triangle (a few triangles per cell,
  // larger ones in several cells); at most about 4M cells.
  const Vec3 size = hi - lo;
  cell_ = std::max({extent, 1e-12 * size.maxCoeff(), 1e-300});
  while ((size / cell_).array().floor().prod() > 4e6) cell_ *= 2;
  origin_ = lo;
  for (int i = 0; i < 3; ++i) dims_[i] = std::max(1, static_cast<int>(std::floor(size[i] / cell_)) + 1);
  const std::size_t cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  const auto id = [this](int i, int j, int k) { return (static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i; };
  // Two passes (count, fill) over the cells each triangle's box overlaps.
  cell_start_.assign(cells + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> fill;
    if (pass == 1) {
      for (std::size_t i = 0; i < cells; ++i) cell_start_[i + 1] += cell_start_[i];
      cell_items_.resize(cell_start_[cells]);
      fill.assign(cell_start_.begin(), cell_start_.end() - 1);
    }
    for (std::size_t n = 0; n < triangles_.size(); ++n) {
      const auto& t = triangles_[n];
      const std::array<int, 3> a = cell_of(t[0].cwiseMin(t[1]).cwiseMin(t[2]));
      const std::array<int, 3> b = cell_of(t[0].cwiseMax(t[1]).cwiseMax(t[2]));
      for (int k = a[2]; k <= b[2]; ++k)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int i = a[0]; i <= b[0]; ++i) {
            if (pass == 0)
              ++cell_start_[id(i, j, k) + 1];
            else
              cell_items_[fill[id(i, j, k)]++] = static_cast<std::uint32_t>(n);
          }
    }
  }
}

Vec3 DiscreteSurface::closest_point(const Vec3& p) const {
  if (triangles_.empty()) return p;
  const std::array<int, 3> c = cell_of(p);
  const int max_shell = std::max({dims_[0], dims_[1], dims_[2]});
  Vec3 best = p;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int shell = 0; shell <= max_shell; ++shell) {
    // The cells at Chebyshev distance `shell` from c.
    for (int k = c[2] - shell; k <= c[2] + shell; ++k) {
      if (k < 0 || k >= dims_[2]) continue;
      for (int j = c[1] - shell; j <= c[1] + shell; ++j) {
        if (j < 0 || j >= dims_[1]) continue;
        const bool face = std::abs(k - c[2]) == shell || std::abs(j - c[1]) == shell;
        for (int i = c[0] - shell; i <= c[0] + shell; i += face ? 1 : std::max(1, 2 * shell)) {
          if (i < 0 || i >= dims_[0]) continue;
          const std::size_t cell = (static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i;
          for (std::uint32_t q = cell_start_[cell]; q < cell_start_[cell + 1]; ++q) {
            const auto& t = triangles_[cell_items_[q]];
            const Vec3 x = closest_point_on_triangle(p, t[0], t[1], t[2]);
            const double d2 = (x - p).squaredNorm();
            if (d2 < best_d2) {
              best_d2 = d2;
              best = x;
            }
          }
        }
      }
    }
    // Every triangle with a point closer to p than the block of cells
    // searched so far (c +- shell) is in one of its cells; sides at the end
    // of the grid have nothing beyond them.
    double reach = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
      if (c[i] - shell > 0) reach = std::min(reach, p[i] - (origin_[i] + (c[i] - shell) * cell_));
      if (c[i] + shell < dims_[i] - 1) reach = std::min(reach, origin_[i] + (c[i] + shell + 1) * cell_ - p[i]);
    }
    if (reach >= 0 && best_d2 <= reach * reach) break;
  }
  return best;
}

}  // namespace femorph
