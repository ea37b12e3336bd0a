// segment_surface on surfaces built in the test: a box (no curvature
// anywhere), a capped cylinder, a sphere, a profile with a fillet only two
// triangles wide (documented behaviour), and bad input.
#include "mesh/count_coincident_points.h"
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "segment/segmentation.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace femorph {
namespace {

/// A closed prism: the 2D polygon `profile` (counter-clockwise) extruded
/// from z = 0 to z = height in `layers` layers; caps fanned from the
/// polygon's centroid. Triangles face outward.
SurfaceMesh extrude(const std::vector<Eigen::Vector2d>& profile, double height, int layers) {
  std::vector<Vec3> p;
  std::vector<Tri> t;
  const index_t n = static_cast<index_t>(profile.size());
  for (int k = 0; k <= layers; ++k)
    for (const auto& q : profile) p.emplace_back(q.x(), q.y(), height * k / layers);
  auto id = [n](int k, index_t i) { return static_cast<index_t>(k * n + (i % n)); };
  for (int k = 0; k < layers; ++k)
    for (index_t i = 0; i < n; ++i) {
      t.push_back({id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      t.push_back({id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& q : profile) c += q / static_cast<double>(n);
  const index_t bottom = static_cast<index_t>(p.size());
  p.emplace_back(c.x(), c.y(), 0.0);
  const index_t top = static_cast<index_t>(p.size());
  p.emplace_back(c.x(), c.y(), height);
  for (index_t i = 0; i < n; ++i) {
    t.push_back({bottom, id(0, i + 1), id(0, i)});
    t.push_back({top, id(layers, i), id(layers, i + 1)});
  }
  SurfaceMesh s;
  const Status st = build_surface_mesh(p, t, s);
  EXPECT_TRUE(st.ok) << st.message;
  return s;
}

std::map<SurfaceType, int> count_types(const Segmentation& seg) {
  std::map<SurfaceType, int> c;
  for (const Region& r : seg.regions) ++c[r.type];
  return c;
}

Segmentation run(const SurfaceMesh& s, SegmentationParams params = {}) {
  Segmentation seg;
  const Status st = segment_surface(s, params, seg);
  EXPECT_TRUE(st.ok) << st.message;
  return seg;
}

TEST(SegmentSurface, BoxWithoutCurvatureIsSixPlanes) {
  const SurfaceMesh box = extrude({{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 2.0, 3);
  const Segmentation seg = run(box);
  EXPECT_EQ(count_types(seg), (std::map<SurfaceType, int>{{SurfaceType::Plane, 6}}));
  int lines = 0, corners = 0;
  for (const BoundaryCurve& c : seg.curves) lines += c.type == CurveType::Line;
  for (std::int8_t v : seg.vertex_class) corners += v == 3;
  EXPECT_EQ(lines, 12);
  EXPECT_EQ(corners, 8);
  for (const Region& r : seg.regions) {
    EXPECT_EQ(r.neighbors.size(), 4u);
    for (Continuity c : r.continuity) EXPECT_EQ(c, Continuity::G0);
  }
}

TEST(SegmentSurface, CappedCylinderIsACylinderAndTwoPlanes) {
  std::vector<Eigen::Vector2d> circle;
  const double radius = 7.0;
  for (int i = 0; i < 48; ++i) circle.emplace_back(radius * std::cos(2 * kPi * i / 48), radius * std::sin(2 * kPi * i / 48));
  const Segmentation seg = run(extrude(circle, 10.0, 8));
  ASSERT_EQ(count_types(seg), (std::map<SurfaceType, int>{{SurfaceType::Plane, 2}, {SurfaceType::Cylinder, 1}}));
  for (const Region& r : seg.regions)
    if (r.type == SurfaceType::Cylinder) {
      EXPECT_NEAR(r.surface.radius, radius, 1e-9 * radius);
      EXPECT_NEAR(std::abs(r.surface.axis.z()), 1.0, 1e-12);
      EXPECT_EQ(r.convexity, Convexity::Convex);
    }
  ASSERT_EQ(seg.curves.size(), 2u);
  for (const BoundaryCurve& c : seg.curves) {
    EXPECT_EQ(c.type, CurveType::Circle);
    EXPECT_TRUE(c.closed);
    EXPECT_NEAR(c.curve.radius, radius, 1e-9 * radius);
  }
}

TEST(SegmentSurface, SubdividedIcosahedronIsOneSphere) {
  // Icosahedron subdivided three times, projected on a sphere of radius 4.
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> p = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
                         {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  std::vector<Tri> t = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  const double radius = 4.0;
  for (int level = 0; level < 3; ++level) {
    std::map<std::pair<index_t, index_t>, index_t> mid;
    auto midpoint = [&](index_t a, index_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back(0.5 * (p[a] + p[b]));
      return mid[key] = static_cast<index_t>(p.size() - 1);
    };
    std::vector<Tri> next;
    for (const Tri& f : t) {
      const index_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    t.swap(next);
  }
  for (Vec3& q : p) q = radius * q.normalized();
  SurfaceMesh s;
  ASSERT_TRUE(build_surface_mesh(p, t, s).ok);
  const Segmentation seg = run(s);
  ASSERT_EQ(seg.regions.size(), 1u);
  EXPECT_EQ(seg.regions[0].type, SurfaceType::Sphere);
  EXPECT_NEAR(seg.regions[0].surface.radius, radius, 1e-9 * radius);
  EXPECT_LT(seg.regions[0].surface.point.norm(), 1e-9);
  EXPECT_TRUE(seg.curves.empty());
}

// A rectangle profile whose corner is rounded by a quarter circle of radius
// 0.5 cut in two segments: the fillet is two triangles wide (three vertex
// rows). Documented behaviour: it is recognised as a cylinder of the right
// radius when the dihedral angle between its two strips (45 deg) is below
// the sharp angle; with the default sharp angle (30 deg) the middle row is
// a sharp edge, each strip is flat, and the fillet becomes two planes
// (never a wrong curved primitive). Refine such fillets to have them found.
std::vector<Eigen::Vector2d> tiny_fillet_profile(double r) {
  std::vector<Eigen::Vector2d> q = {{0, 0}, {6, 0}};
  for (int i = 0; i <= 2; ++i) {
    const double a = -kPi / 2 + (kPi / 2) * i / 2;  // quarter circle in two segments
    q.emplace_back(6 - r + r * std::cos(a), 4 - r + r * std::sin(a));
  }
  q.emplace_back(0, 4);
  return q;
}

TEST(SegmentSurface, TinyFilletTwoTrianglesWide) {
  const double r = 0.5;
  const SurfaceMesh s = extrude(tiny_fillet_profile(r), 3.0, 6);
  {
    // Default: two flat strips.
    const Segmentation seg = run(s);
    const auto types = count_types(seg);
    EXPECT_EQ(types.count(SurfaceType::Cylinder), 0u);
    EXPECT_EQ(types.at(SurfaceType::Plane), 8);  // 4 sides + 2 caps + 2 strips
    EXPECT_EQ(types.size(), 1u);
  }
  {
    SegmentationParams params;
    params.sharp_angle_deg = 60;  // the strips' 45 deg bend is no longer sharp
    const Segmentation seg = run(s, params);
    const auto types = count_types(seg);
    ASSERT_EQ(types.count(SurfaceType::Cylinder), 1u);
    for (const Region& region : seg.regions)
      if (region.type == SurfaceType::Cylinder) {
        EXPECT_NEAR(region.surface.radius, r, 1e-9 * r);
        EXPECT_EQ(region.convexity, Convexity::Convex);
      }
  }
}

TEST(SegmentSurface, DegenerateTrianglesJoinTheirPlane) {
  // A box with a zero-area triangle: the cap triangle (top, a, b) keeps its
  // edge a -> b; on the other side the face triangle (b, a, x) is replaced by
  // (m, a, x), (b, m, x) and the flat (b, a, m), m the midpoint of ab. Still
  // closed and manifold, still six planes.
  const SurfaceMesh box = extrude({{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 2.0, 1);
  std::vector<Vec3> p = box.points;
  std::vector<Tri> t = box.triangles;
  const Tri cap = t.back();
  const index_t a = cap[1], b = cap[2];
  const index_t m = static_cast<index_t>(p.size());
  p.push_back(0.5 * (p[a] + p[b]));
  bool replaced = false;
  for (Tri& f : t)
    for (int k = 0; k < 3 && !replaced; ++k)
      if (f[k] == b && f[(k + 1) % 3] == a) {
        const index_t x = f[(k + 2) % 3];
        f = {m, a, x};
        t.push_back({b, m, x});
        t.push_back({b, a, m});
        replaced = true;
      }
  ASSERT_TRUE(replaced);
  SurfaceMesh s;
  SurfaceReport report;
  ASSERT_TRUE(build_surface_mesh(p, t, s, false, &report).ok);
  EXPECT_EQ(report.degenerate_triangles, 1u);
  const Segmentation seg = run(s);
  EXPECT_EQ(count_types(seg), (std::map<SurfaceType, int>{{SurfaceType::Plane, 6}}));
}

TEST(SegmentSurface, RefusesAnEmptySurfaceAndBadTolerance) {
  SurfaceMesh empty;
  Segmentation seg;
  EXPECT_FALSE(segment_surface(empty, {}, seg).ok);
  const SurfaceMesh box = extrude({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1.0, 1);
  SegmentationParams bad;
  bad.distance_tolerance = 0;
  const Status st = segment_surface(box, bad, seg);
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("tolerance"), std::string::npos);
}

TEST(SegmentSurface, OpenAndNonManifoldSurfacesAreRefusedByTheSurfaceMesh) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  SurfaceMesh s;
  Status st = build_surface_mesh(p, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}}, s);  // a tet missing a face
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("open"), std::string::npos) << st.message;
  p.push_back({0, 0, -1});
  st = build_surface_mesh(p, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}, {0, 1, 4}}, s);  // edge (0,1) thrice
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("manifold"), std::string::npos) << st.message;
}

TEST(SegmentSurface, AbortFromProgress) {
  const SurfaceMesh box = extrude({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1.0, 1);
  Segmentation seg;
  int calls = 0;
  const Status st = segment_surface(box, {}, seg, [&](double, const char*) { return ++calls < 3; });
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("abort"), std::string::npos);
}

TEST(SegmentSurface, DeterministicForASeed) {
  std::vector<Eigen::Vector2d> circle;
  for (int i = 0; i < 40; ++i) circle.emplace_back(3 * std::cos(2 * kPi * i / 40), 3 * std::sin(2 * kPi * i / 40));
  const SurfaceMesh s = extrude(circle, 5.0, 5);
  const Segmentation a = run(s), b = run(s);
  EXPECT_EQ(a.triangle_region, b.triangle_region);
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (std::size_t i = 0; i < a.regions.size(); ++i) {
    EXPECT_EQ(a.regions[i].surface.radius, b.regions[i].surface.radius);
    EXPECT_EQ(a.regions[i].surface.point, b.regions[i].surface.point);
  }
}

}  // namespace
}  // namespace femorph

namespace femorph {
namespace {

// count_coincident_points: within the tolerance (inclusive) or not, exact
// duplicates with tolerance 0, far from the origin, and many points.
TEST(CountCoincidentPoints, ToleranceAndDuplicates) {
  EXPECT_EQ(count_coincident_points({}, 1.0), 0u);
  EXPECT_EQ(count_coincident_points({Vec3(0, 0, 0)}, 1.0), 0u);
  const std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(1e-7, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  EXPECT_EQ(count_coincident_points(p, 0.0), 2u);   // the two at x = 1
  EXPECT_EQ(count_coincident_points(p, 1e-6), 4u);  // and the pair near 0
  EXPECT_EQ(count_coincident_points(p, 1.0), 5u);   // distance 1 counts
  std::vector<Vec3> far;
  for (int i = 0; i < 1000; ++i) far.push_back(Vec3(1e9 + i * 0.5, 3e9, -2e9 + (i % 7)));
  EXPECT_EQ(count_coincident_points(far, 1e-6), 0u);
  far.push_back(far[500]);
  EXPECT_EQ(count_coincident_points(far, 1e-6), 2u);
}

// Issue 29: a part meshed in two halves whose points on the common face were
// not merged (an unmerged seam) has a closed boundary inside; segment_boundary
// must say so, with the count and what to do, instead of returning many
// regions silently. The merged part (control) gets no such warning.
TEST(SegmentBoundary, WarnsAboutAnUnmergedSeam) {
  const int n = 3;
  const testing::TestMesh half = testing::make_cube_mesh(n, 0.0, 1);
  std::vector<Vec3> points = half.points;
  std::vector<Tet> tets = half.tets;
  const index_t offset = static_cast<index_t>(points.size());
  for (const Vec3& x : half.points) points.push_back(x + Vec3(1, 0, 0));
  for (Tet t : half.tets) {
    for (index_t& v : t) v += offset;
    tets.push_back(t);
  }
  TetMesh seamed;
  ASSERT_TRUE(seamed.build(points, tets).ok);
  SurfaceMesh surface;
  Segmentation seg;
  ASSERT_TRUE(segment_boundary(seamed, SegmentationParams{}, surface, seg).ok);
  std::string warnings;
  for (const std::string& w : seg.warnings) warnings += w + "\n";
  const std::size_t seam_points = 2 * (n + 1) * (n + 1);
  EXPECT_NE(warnings.find(std::to_string(seam_points) + " boundary points lie on top of other boundary points"),
            std::string::npos)
      << warnings;
  EXPECT_NE(warnings.find("Merge coincident points first"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("Clean to Grid"), std::string::npos) << warnings;

  TetMesh whole;
  const testing::TestMesh cube = testing::make_cube_mesh(n, 0.0, 1);
  ASSERT_TRUE(whole.build(cube.points, cube.tets).ok);
  Segmentation control;
  ASSERT_TRUE(segment_boundary(whole, SegmentationParams{}, surface, control).ok);
  for (const std::string& w : control.warnings) EXPECT_EQ(w.find("lie on top"), std::string::npos) << w;
}


/// A closed surface of revolution about the z axis: the profile (rho, z)
/// runs from a point on the axis to another one; n segments around.
SurfaceMesh revolve(const std::vector<Eigen::Vector2d>& profile, int n) {
  std::vector<Vec3> p;
  std::vector<Tri> t;
  p.emplace_back(0, 0, profile.front().y());
  const index_t rings = static_cast<index_t>(profile.size()) - 2;
  for (index_t i = 1; i <= rings; ++i)
    for (int k = 0; k < n; ++k) {
      const double a = 2 * kPi * k / n;
      p.emplace_back(profile[i].x() * std::cos(a), profile[i].x() * std::sin(a), profile[i].y());
    }
  p.emplace_back(0, 0, profile.back().y());
  const index_t top = static_cast<index_t>(p.size()) - 1;
  auto id = [n](index_t ring, int k) { return 1 + (ring - 1) * n + (k % n); };
  for (int k = 0; k < n; ++k) {
    t.push_back({0, id(1, k + 1), id(1, k)});
    for (index_t i = 1; i < rings; ++i) {
      t.push_back({id(i, k), id(i, k + 1), id(i + 1, k + 1)});
      t.push_back({id(i, k), id(i + 1, k + 1), id(i + 1, k)});
    }
    t.push_back({top, id(rings, k), id(rings, k + 1)});
  }
  SurfaceMesh s;
  EXPECT_TRUE(build_surface_mesh(p, t, s).ok);
  return s;
}

TEST(SegmentSurface, SpindleTorusBossEnd) {
  // A boss of radius R + r = 19.2 whose end is rounded by a spindle torus
  // (major radius R = 9.2 below the minor radius r = 10, issue 28): tangent
  // to the side cylinder, it reaches the axis in a dimple. Planar bottom.
  const double R = 9.2, r = 10, h = 10;
  std::vector<Eigen::Vector2d> q;
  for (int i = 0; i <= 8; ++i) q.emplace_back((R + r) * i / 8.0, -h);
  for (int i = 1; i <= 10; ++i) q.emplace_back(R + r, -h + h * i / 10.0);
  const double end = std::acos(-R / r);
  for (int i = 1; i <= 40; ++i) {
    const double a = end * i / 40.0;
    q.emplace_back(R + r * std::cos(a), r * std::sin(a));
  }
  q.back().x() = 0;
  const SurfaceMesh s = revolve(q, 72);
  const Segmentation seg = run(s);
  const auto types = count_types(seg);
  EXPECT_EQ(types.count(SurfaceType::Unknown), 0u);
  ASSERT_EQ(types.count(SurfaceType::Torus), 1u);
  EXPECT_EQ(types.at(SurfaceType::Torus), 1);
  for (const Region& region : seg.regions)
    if (region.type == SurfaceType::Torus) {
      EXPECT_NEAR(region.surface.radius, R, 1e-6 * R);
      EXPECT_NEAR(region.surface.minor_radius, r, 1e-6 * r);
      EXPECT_LT(std::abs(std::abs(region.surface.axis.z()) - 1), 1e-9);
    }
}

}  // namespace
}  // namespace femorph
