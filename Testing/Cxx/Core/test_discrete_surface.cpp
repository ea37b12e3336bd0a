// The kept triangles of a region without a fit (Core/geometry/discrete_surface):
// the closest point on a triangle in each of its regions, and the grid
// search against a brute-force scan.
#include "geometry/discrete_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace femorph {
namespace {

TEST(ClosestPointOnTriangle, EachRegion) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  const auto near = [](const Vec3& x, const Vec3& y) { return (x - y).norm() < 1e-15; };
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(0.5, 0.5, 3), a, b, c), Vec3(0.5, 0.5, 0)));  // inside
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(-1, -1, 1), a, b, c), a));                    // vertices
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(3, -1, 0), a, b, c), b));
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(-1, 3, 0), a, b, c), c));
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(1, -1, 2), a, b, c), Vec3(1, 0, 0)));  // edges
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(-1, 1, 0), a, b, c), Vec3(0, 1, 0)));
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(2, 2, -1), a, b, c), Vec3(1, 1, 0)));
  // Degenerate: three points on a line, and a point triangle.
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(1, 1, 0), a, b, Vec3(1, 0, 0)), Vec3(1, 0, 0)));
  EXPECT_TRUE(near(closest_point_on_triangle(Vec3(1, 1, 0), a, a, a), a));
}

// A wavy, uneven triangulated sheet: the grid search finds the same
// distance as scanning every triangle, for points near it and far away.
TEST(DiscreteSurface, GridSearchMatchesBruteForce) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 30;
  auto height = [](double x, double y) { return 0.3 * std::sin(3 * x) * std::cos(2 * y); };
  std::vector<std::array<Vec3, 3>> triangles;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Uneven columns: wide and narrow cells.
      const double x0 = std::pow(static_cast<double>(i) / n, 2), x1 = std::pow(static_cast<double>(i + 1) / n, 2);
      const double y0 = static_cast<double>(j) / n, y1 = static_cast<double>(j + 1) / n;
      const Vec3 p00(x0, y0, height(x0, y0)), p10(x1, y0, height(x1, y0)), p01(x0, y1, height(x0, y1)),
          p11(x1, y1, height(x1, y1));
      triangles.push_back({p00, p10, p11});
      triangles.push_back({p00, p11, p01});
    }
  DiscreteSurface surface;
  surface.build(triangles);
  ASSERT_EQ(surface.size(), triangles.size());
  for (int k = 0; k < 500; ++k) {
    const double spread = k < 400 ? 0.1 : 3.0;  // near the sheet, then far
    const Vec3 p(u(rng), u(rng), height(u(rng), u(rng)) + spread * (2 * u(rng) - 1));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : triangles) best = std::min(best, (closest_point_on_triangle(p, t[0], t[1], t[2]) - p).norm());
    EXPECT_NEAR((surface.closest_point(p) - p).norm(), best, 1e-14) << k;
  }
  DiscreteSurface none;
  EXPECT_EQ(none.closest_point(Vec3(1, 2, 3)), Vec3(1, 2, 3));
}

}  // namespace
}  // namespace femorph
