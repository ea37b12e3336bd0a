// G_d, the distance field grid of thesis 3.4.1 (Fig. 3.2): cells holding a
// surface vertex of the moving object start at distance 0, and the
// simplified fast marching gives each further cell the distance of the
// nearest known cell plus one, up to the threshold. Built once in the
// object's frame at step 0; it moves with the object (a point is mapped
// into that frame to be looked up), which is the thesis' T_i applied to G_d.
#include "adapt/adapt.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace femorph {

double DistanceGrid::at(const Vec3& x) const {
  const Vec3 q = (x - origin) / h;
  int c[3];
  for (int a = 0; a < 3; ++a) {
    c[a] = static_cast<int>(std::floor(q[a]));
    if (c[a] < 0 || c[a] >= n[a]) return std::numeric_limits<double>::infinity();
  }
  return distance[(static_cast<std::size_t>(c[2]) * n[1] + c[1]) * n[0] + c[0]];
}

DistanceGrid build_distance_grid(const std::vector<Vec3>& surface_points, double h, double threshold) {
  DistanceGrid g;
  g.h = h;
  if (surface_points.empty()) return g;
  Vec3 lo = surface_points[0], hi = lo;
  for (const Vec3& p : surface_points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // The padding holds every cell the marching can reach below the threshold.
  const double pad = (std::ceil(threshold) + 1) * h;
  g.origin = lo - Vec3::Constant(pad);
  for (int a = 0; a < 3; ++a) g.n[a] = std::max(1, static_cast<int>(std::ceil((hi[a] + pad - g.origin[a]) / h)));
  const std::size_t cells = static_cast<std::size_t>(g.n[0]) * g.n[1] * g.n[2];
  g.distance.assign(cells, std::numeric_limits<float>::infinity());
  const auto id = [&](int i, int j, int k) { return (static_cast<std::size_t>(k) * g.n[1] + j) * g.n[0] + i; };
  // Step 1: trial cells at distance 0. Unit steps make the trial list a FIFO
  // (Step 2's minimum is always at its front).
  std::queue<std::array<int, 3>> trial;
  for (const Vec3& p : surface_points) {
    const Vec3 q = (p - g.origin) / h;
    std::array<int, 3> c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor(q[a])), 0, g.n[a] - 1);
    float& d = g.distance[id(c[0], c[1], c[2])];
    if (d != 0) {
      d = 0;
      trial.push(c);
    }
  }
  // Step 2: pop the nearest, label its far neighbours d + 1, until the
  // threshold.
  while (!trial.empty()) {
    const std::array<int, 3> c = trial.front();
    trial.pop();
    const float d = g.distance[id(c[0], c[1], c[2])];
    if (d + 1 > threshold + 1) continue;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
          if (i < 0 || j < 0 || k < 0 || i >= g.n[0] || j >= g.n[1] || k >= g.n[2]) continue;
          float& e = g.distance[id(i, j, k)];
          if (e <= d + 1) continue;
          e = d + 1;
          trial.push({i, j, k});
        }
  }
  return g;
}

}  // namespace femorph
