// constrained_delaunay_2d: checked by brute force (orientation, coverage of
// the convex hull by area, each segment a chain of edges, the constrained
// Delaunay property edge by edge) on seeded random inputs and on the
// degenerate cases Adapt's contact regions produce (grids, collinear points
// on segments).
#include "geometry/triangulate_2d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

namespace femorph {
namespace {

double cross(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

double hull_area(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  std::vector<Vec2> h;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t start = h.size();
    for (const Vec2& q : p) {
      while (h.size() >= start + 2 && cross(h[h.size() - 2], h.back(), q) <= 0) h.pop_back();
      h.push_back(q);
    }
    h.pop_back();
    std::reverse(p.begin(), p.end());
  }
  double a = 0;
  for (std::size_t i = 0; i < h.size(); ++i) a += cross(Vec2::Zero(), h[i], h[(i + 1) % h.size()]);
  return 0.5 * a;
}

// Edges of the triangulation, with the triangles on each side.
std::map<std::pair<index_t, index_t>, std::vector<index_t>> edges_of(const std::vector<Triangle>& tris) {
  std::map<std::pair<index_t, index_t>, std::vector<index_t>> e;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      const index_t a = tris[t][i], b = tris[t][(i + 1) % 3];
      e[{std::min(a, b), std::max(a, b)}].push_back(static_cast<index_t>(t));
    }
  return e;
}

// A segment is a chain of edges: every point on it (strictly inside) is a
// vertex, and the consecutive pairs are edges.
bool segment_is_chain(const std::vector<Vec2>& p, const Segment2& s,
                      const std::map<std::pair<index_t, index_t>, std::vector<index_t>>& edges) {
  const Vec2 d = p[s[1]] - p[s[0]];
  std::vector<std::pair<double, index_t>> on{{0.0, s[0]}, {1.0, s[1]}};
  for (std::size_t v = 0; v < p.size(); ++v) {
    const index_t i = static_cast<index_t>(v);
    if (i == s[0] || i == s[1]) continue;
    if (cross(p[s[0]], p[s[1]], p[v]) != 0) continue;
    const double t = (p[v] - p[s[0]]).dot(d) / d.squaredNorm();
    if (t > 0 && t < 1) on.push_back({t, i});
  }
  std::sort(on.begin(), on.end());
  for (std::size_t k = 0; k + 1 < on.size(); ++k) {
    const index_t a = on[k].second, b = on[k + 1].second;
    if (!edges.count({std::min(a, b), std::max(a, b)})) return false;
  }
  return true;
}

void check(const std::vector<Vec2>& p, const std::vector<Segment2>& segs, const std::vector<Triangle>& tris) {
  double area = 0;
  for (const Triangle& t : tris) {
    const double a = cross(p[t[0]], p[t[1]], p[t[2]]);
    ASSERT_GT(a, 0) << "a triangle is not counter-clockwise";
    area += 0.5 * a;
  }
  EXPECT_NEAR(area, hull_area(p), 1e-9 * hull_area(p)) << "the triangles do not tile the convex hull";
  const auto edges = edges_of(tris);
  std::set<std::pair<index_t, index_t>> constrained;
  for (const auto& [e, ts] : edges) ASSERT_LE(ts.size(), 2u);
  for (const Segment2& s : segs) {
    EXPECT_TRUE(segment_is_chain(p, s, edges)) << "segment " << s[0] << "-" << s[1] << " is not a chain of edges";
  }
  // Constrained Delaunay: an edge that is no segment's piece has no vertex of
  // the opposite triangle strictly inside the circumcircle of the other.
  std::set<std::pair<index_t, index_t>> on_segment;
  for (const Segment2& s : segs) {
    const Vec2 d = p[s[1]] - p[s[0]];
    for (const auto& [e, ts] : edges) {
      const Vec2 a = p[e.first], b = p[e.second];
      if (cross(p[s[0]], p[s[1]], a) == 0 && cross(p[s[0]], p[s[1]], b) == 0) {
        const double ta = (a - p[s[0]]).dot(d) / d.squaredNorm(), tb = (b - p[s[0]]).dot(d) / d.squaredNorm();
        if (ta >= 0 && ta <= 1 && tb >= 0 && tb <= 1) on_segment.insert(e);
      }
    }
  }
  for (const auto& [e, ts] : edges) {
    if (ts.size() != 2 || on_segment.count(e)) continue;
    const Triangle& A = tris[ts[0]];
    const Triangle& B = tris[ts[1]];
    index_t opposite = kInvalidIndex;
    for (const index_t v : B)
      if (v != e.first && v != e.second) opposite = v;
    // In-circle determinant, in double: inputs are well conditioned here.
    const Vec2 a = p[A[0]] - p[opposite], b = p[A[1]] - p[opposite], c = p[A[2]] - p[opposite];
    const double det = a.squaredNorm() * (b.x() * c.y() - b.y() * c.x()) -
                       b.squaredNorm() * (a.x() * c.y() - a.y() * c.x()) +
                       c.squaredNorm() * (a.x() * b.y() - a.y() * b.x());
    const double scale = a.squaredNorm() * b.norm() * c.norm() + b.squaredNorm() * a.norm() * c.norm() +
                         c.squaredNorm() * a.norm() * b.norm();
    EXPECT_LE(det, 1e-9 * scale) << "edge " << e.first << "-" << e.second << " is not locally Delaunay";
  }
}

TEST(ConstrainedDelaunay2D, RandomPointsAreDelaunay) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec2> p;
  for (int i = 0; i < 2000; ++i) p.emplace_back(u(rng), u(rng));
  std::vector<Triangle> tris;
  ASSERT_TRUE(constrained_delaunay_2d(p, {}, tris));
  check(p, {}, tris);
  // Euler: 2n - 2 - h triangles, h hull vertices (at least 3).
  EXPECT_LE(tris.size(), 2 * p.size() - 5);
  EXPECT_GE(tris.size(), 2 * p.size() - 2 - 60);
}

TEST(ConstrainedDelaunay2D, SegmentsAcrossRandomPointsAreEdges) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec2> p;
  for (int i = 0; i < 1000; ++i) p.emplace_back(u(rng), u(rng));
  // A closed polygon of long segments (a star), none crossing.
  const int k = 9;
  const Vec2 c(0.5, 0.5);
  const index_t first = static_cast<index_t>(p.size());
  for (int i = 0; i < k; ++i) {
    const double r = (i % 2 ? 0.2 : 0.45), a = 2 * kPi * i / k;
    p.push_back(c + r * Vec2(std::cos(a), std::sin(a)));
  }
  std::vector<Segment2> segs;
  for (int i = 0; i < k; ++i) segs.push_back({{first + i, first + (i + 1) % k}});
  std::vector<Triangle> tris;
  std::vector<index_t> component;
  ASSERT_TRUE(constrained_delaunay_2d(p, segs, tris, &component));
  check(p, segs, tris);
  // Two regions: inside the star and outside it.
  EXPECT_EQ(*std::max_element(component.begin(), component.end()), 1);
  double inside = 0, star = 0;
  const index_t centre_region = [&] {
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const Vec2 g = (p[tris[t][0]] + p[tris[t][1]] + p[tris[t][2]]) / 3;
      if ((g - c).norm() < 0.05) return component[t];
    }
    return kInvalidIndex;
  }();
  for (std::size_t t = 0; t < tris.size(); ++t)
    if (component[t] == centre_region) inside += 0.5 * cross(p[tris[t][0]], p[tris[t][1]], p[tris[t][2]]);
  for (int i = 0; i < k; ++i) star += 0.5 * cross(c, p[first + i], p[first + (i + 1) % k]);
  EXPECT_NEAR(inside, star, 1e-12) << "the region inside the star is not the star";
}

TEST(ConstrainedDelaunay2D, GridWithCollinearPointsOnSegments) {
  // A regular grid (all cocircular quads) with segments along grid lines
  // through many grid points and along a diagonal: the cases of development
  // planes of structured cylinders.
  std::vector<Vec2> p;
  const int n = 12;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) p.emplace_back(i, j);
  const auto id = [&](int i, int j) { return static_cast<index_t>(j * (n + 1) + i); };
  const std::vector<Segment2> segs{{{id(0, 3), id(n, 3)}}, {{id(5, 0), id(5, n)}}, {{id(0, 0), id(n, n)}},
                                   {{id(1, 10), id(4, 11)}}};
  std::vector<Triangle> tris;
  std::vector<index_t> component;
  ASSERT_TRUE(constrained_delaunay_2d(p, segs, tris, &component));
  check(p, segs, tris);
  EXPECT_EQ(tris.size(), static_cast<std::size_t>(2 * n * n));
}

TEST(ConstrainedDelaunay2D, BadInputIsAnError) {
  std::vector<Triangle> tris;
  const std::vector<Vec2> square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const Status crossing = constrained_delaunay_2d(square, {{{0, 2}}, {{1, 3}}}, tris);
  EXPECT_FALSE(crossing);
  EXPECT_NE(crossing.message.find("crosses"), std::string::npos) << crossing.message;
  const Status duplicate = constrained_delaunay_2d({{0, 0}, {1, 0}, {0, 1}, {1, 0}}, {}, tris);
  EXPECT_FALSE(duplicate);
  EXPECT_NE(duplicate.message.find("coincide"), std::string::npos) << duplicate.message;
  EXPECT_FALSE(constrained_delaunay_2d({{0, 0}, {1, 1}, {2, 2}}, {}, tris));
  EXPECT_FALSE(constrained_delaunay_2d(square, {{{0, 7}}}, tris));
  EXPECT_FALSE(constrained_delaunay_2d({{0, 0}, {1, 0}, {0, std::nan("")}}, {}, tris));
}

}  // namespace
}  // namespace femorph
