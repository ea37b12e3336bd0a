// Coincident points by a spatial hash: each point's grid cell (of the
// tolerance's size), the points sorted by cell, and every point compared with
// the points of its own and the 26 neighbouring cells only.
#include "mesh/count_coincident_points.h"
#include "common/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>

namespace femorph {

std::size_t count_coincident_points(const std::vector<Vec3>& points, double tolerance) {
  const std::size_t n = points.size();
  if (n < 2) return 0;
  using Key = std::array<std::int64_t, 3>;
  // Cell size: the tolerance, or for exact duplicates any size (equal
  // points share a cell whatever it is): the extent over 2^20.
  double cell = tolerance;
  if (!(cell > 0)) {
    Vec3 lo = points[0], hi = points[0];
    for (const Vec3& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    cell = std::max((hi - lo).maxCoeff(), 1e-300) / (1 << 20);
  }
  // Keys relative to the first point, so that far-away coordinates with a
  // small tolerance still fit 64 bits (clamped: such a part would have more
  // than 2^62 cells across).
  const Vec3 origin = points[0];
  const auto key_of = [&](const Vec3& p) {
    Key k;
    for (int a = 0; a < 3; ++a)
      k[a] = static_cast<std::int64_t>(std::clamp(std::floor((p[a] - origin[a]) / cell), -4e18, 4e18));
    return k;
  };
  std::vector<std::pair<Key, index_t>> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = {key_of(points[i]), static_cast<index_t>(i)};
  std::sort(order.begin(), order.end());

  // The cells (x, y, z - 1 .. z + 1) of one column are consecutive in the
  // sorted order: one search per column, nine per point.
  const double tolerance2 = tolerance * tolerance;
  const auto key_less = [](const std::pair<Key, index_t>& e, const Key& key) { return e.first < key; };
  const std::size_t count = parallel_reduce(
      static_cast<long>(n), std::size_t(0),
      [&](long begin, long end, int) {
        std::size_t k_count = 0;
        for (std::size_t i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
          const Key& k = order[i].first;
          const Vec3& p = points[static_cast<std::size_t>(order[i].second)];
          bool found = false;
          for (int dx = -1; dx <= 1 && !found; ++dx)
            for (int dy = -1; dy <= 1 && !found; ++dy) {
              const Key lo{{k[0] + dx, k[1] + dy, k[2] - 1}}, hi{{k[0] + dx, k[1] + dy, k[2] + 1}};
              auto it = std::lower_bound(order.begin(), order.end(), lo, key_less);
              for (; it != order.end() && !(hi < it->first) && !found; ++it)
                found = it->second != order[i].second &&
                        (points[static_cast<std::size_t>(it->second)] - p).squaredNorm() <= tolerance2;
            }
          k_count += found;
        }
        return k_count;
      },
      std::plus<std::size_t>());
  return count;
}

}  // namespace femorph
