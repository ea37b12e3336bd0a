// Phases (1) and (2) of Phased ODT smoothing (thesis 2.6.5.2, 2.6.5.3):
// ODT smoothing of the curve and surface vertices on their fitted curves and
// surfaces, and the Delaunay surface edge flips of Fig. 2.45.
#include "improve/boundary_geometry.h"
#include "improve/flip_surface_edges.h"
#include "improve/odt_smooth_curves.h"
#include "improve/odt_smooth_surface.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "test_improve_meshes.h"
#include "test_meshes.h"
#include "test_threads.h"
#include "test_surfaces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <random>

namespace femorph {
namespace {

using namespace testing::improve_meshes;

using test_surfaces::cone;
using test_surfaces::cylinder;
using test_surfaces::plane;
using test_surfaces::sphere;
using test_surfaces::torus;

constexpr double kDeg = 180 / kPi;

/// Moves every boundary vertex (id order) within its surface or curve: by up
/// to `amplitude` cells along the grid axes on which it is not on a boundary
/// plane. Moves that would invert are refused by TetMesh. Returns the count.
int perturb_boundary(TetMesh& mesh, const Grid& g, const GridMesh& gm, double amplitude, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  int moved = 0;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    double c[3];
    bool boundary = false;
    for (int a = 0; a < 3; ++a) {
      const int i = gm.ijk[v][a];
      const bool fixed = !g.periodic[a] && (i == 0 || i == g.n[a]);
      const double d = u(rng);  // drawn always: one stream
      c[a] = fixed ? i : i + d;
      boundary = boundary || fixed;
    }
    if (!boundary) continue;
    moved += mesh.move_vertex(v, g.map(c[0], c[1], c[2])) == OpStatus::Ok;
  }
  return moved;
}

// ---- measurements -------------------------------------------------------------

struct BoundaryFace {
  index_t v[3];
  index_t region;
};

std::vector<BoundaryFace> boundary_faces(const TetMesh& mesh) {
  std::vector<BoundaryFace> faces;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f)
      if (mesh.is_boundary_face(t, f)) {
        const Tet& T = mesh.tet(t);
        faces.push_back({{T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]}, mesh.face_region(t, f)});
      }
  }
  return faces;
}

double angle_at(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 a = q - p, b = r - p;
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

double triangle_min_angle(const TetMesh& mesh, const BoundaryFace& f) {
  const Vec3 &a = mesh.point(f.v[0]), &b = mesh.point(f.v[1]), &c = mesh.point(f.v[2]);
  return std::min({angle_at(a, b, c), angle_at(b, c, a), angle_at(c, a, b)});
}

struct AngleStats {
  double min = 0, mean = 0;  // degrees: smallest angle of all triangles, mean of their minimum angles
};

/// Over the boundary triangles of the regions `keep` accepts.
AngleStats angle_stats(const TetMesh& mesh, const std::function<bool(index_t)>& keep = nullptr) {
  AngleStats s;
  s.min = 180;
  int n = 0;
  for (const BoundaryFace& f : boundary_faces(mesh)) {
    if (keep && !keep(f.region)) continue;
    const double a = triangle_min_angle(mesh, f) * kDeg;
    s.min = std::min(s.min, a);
    s.mean += a;
    ++n;
  }
  s.mean /= std::max(n, 1);
  return s;
}

/// Surface edges between two triangles of one region that are not Delaunay
/// (opposite angles summing to more than pi).
int non_delaunay_edges(const TetMesh& mesh, const std::function<bool(index_t)>& keep = nullptr) {
  std::map<std::pair<index_t, index_t>, std::vector<std::pair<index_t, index_t>>> edges;  // -> (apex, region)
  for (const BoundaryFace& f : boundary_faces(mesh))
    for (int e = 0; e < 3; ++e) {
      const index_t a = f.v[e], b = f.v[(e + 1) % 3], c = f.v[(e + 2) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({c, f.region});
    }
  int count = 0;
  for (const auto& [e, apices] : edges) {
    if (apices.size() != 2 || apices[0].second != apices[1].second) continue;
    if (keep && !keep(apices[0].second)) continue;
    const Vec3 &a = mesh.point(e.first), &b = mesh.point(e.second);
    const double sum = angle_at(mesh.point(apices[0].first), a, b) + angle_at(mesh.point(apices[1].first), a, b);
    count += sum > kPi + 1e-9;
  }
  return count;
}

/// Largest distance of a vertex of a boundary face to its region's surface,
/// relative to `scale`.
double max_surface_distance(const TetMesh& mesh, const BoundaryGeometry& geometry, double scale,
                            const std::function<bool(index_t)>& keep = nullptr) {
  double worst = 0;
  for (const BoundaryFace& f : boundary_faces(mesh)) {
    if (keep && !keep(f.region)) continue;
    for (index_t v : f.v) worst = std::max(worst, distance(geometry.regions[f.region], mesh.point(v)) / scale);
  }
  return worst;
}

void expect_valid(const TetMesh& mesh, double volume) {
  ASSERT_TRUE(mesh.check_consistency().ok) << mesh.check_consistency().message;
  const CompactMesh out = mesh.compact();
  const ValidityReport report = check_validity(out.points, out.tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  if (volume > 0) {
    EXPECT_NEAR(testing::total_volume(out.points, out.tets), volume, 1e-12 * volume);
  }
}

double mesh_volume(const TetMesh& mesh) {
  const CompactMesh out = mesh.compact();
  return testing::total_volume(out.points, out.tets);
}

bool same_point(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0; }

void run_phases(TetMesh& mesh, const BoundaryGeometry& geometry, int iterations, OdtSmoothReport* curves,
                OdtSmoothReport* surface, const std::vector<std::uint8_t>& mask = {}) {
  BoundarySmoothOptions options;
  options.iterations = iterations;
  options.vertex_mask = mask;
  *curves = odt_smooth_curves(mesh, geometry, options);
  *surface = odt_smooth_surface(mesh, geometry, options);
}

// ---- the unit cube: six planes, twelve lines ---------------------------------------

BoundaryGeometry cube_geometry(bool with_curves) {
  BoundaryGeometry g;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) g.regions.push_back(plane(side * Vec3::Unit(axis), Vec3::Unit(axis)));
  if (!with_curves) return g;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      for (int s = 0; s < 2; ++s)
        for (int t = 0; t < 2; ++t) {
          const int c = 3 - a - b;
          const Vec3 start = s * Vec3::Unit(a) + t * Vec3::Unit(b);
          g.curves.push_back(line_curve(start, start + Vec3::Unit(c)));
          g.curve_regions.push_back({{2 * a + s, 2 * b + t}});
        }
  return g;
}

/// Moves the boundary vertices of the cube within their faces and edges (the
/// coordinates that are not 0 or 1) by up to `amplitude` / n.
int perturb_cube_boundary(TetMesh& mesh, int n, double amplitude, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude / n, amplitude / n);
  int moved = 0;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    Vec3 p = mesh.point(v);
    bool boundary = false;
    for (int a = 0; a < 3; ++a) boundary = boundary || p[a] == 0 || p[a] == 1;
    if (!boundary) continue;
    for (int a = 0; a < 3; ++a) {
      const double d = u(rng);
      if (p[a] != 0 && p[a] != 1) p[a] += d;
    }
    moved += mesh.move_vertex(v, p) == OpStatus::Ok;
  }
  return moved;
}

void expect_on_cube(const TetMesh& mesh) {
  double worst = 0;
  for (const BoundaryFace& f : boundary_faces(mesh))
    for (index_t v : f.v) worst = std::max(worst, std::abs(mesh.point(v)[f.region / 2] - (f.region % 2)));
  EXPECT_LE(worst, 1e-12);
}

TEST(OdtSmoothBoundary, CubeFacesAndEdgesImproveOnTheirPlanesAndLines) {
  for (const bool with_curves : {true, false}) {
    SCOPED_TRACE(with_curves ? "Line curves" : "two planes per curve");
    const int n = 6;
    TetMesh mesh = build(testing::make_cube_mesh(n, 0.1, 7));
    ASSERT_GT(perturb_cube_boundary(mesh, n, 0.3, 11), 100);
    const BoundaryGeometry geometry = cube_geometry(with_curves);
    const TetMesh before = mesh;
    const AngleStats a0 = angle_stats(mesh);
    OdtSmoothReport rc, rs;
    run_phases(mesh, geometry, 5, &rc, &rs);
    const AngleStats a1 = angle_stats(mesh);
    std::printf("cube (%s): boundary min angle %.2f -> %.2f deg, mean min angle %.2f -> %.2f; curves moved %zu "
                "refused %zu, surface moved %zu refused %zu halvings %zu, last step %.2e\n",
                with_curves ? "lines" : "planes", a0.min, a1.min, a0.mean, a1.mean, rc.moved, rc.refused, rs.moved,
                rs.refused, rs.halvings, rs.last_max_step);
    EXPECT_GT(a1.min, a0.min + 1);
    EXPECT_GT(a1.mean, a0.mean + 1);
    EXPECT_GT(rc.moved, 0u);
    EXPECT_GT(rs.moved, 0u);
    expect_on_cube(mesh);
    expect_valid(mesh, 1.0);
    for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
      if (mesh.vertex_class(v) == VertexClass::Corner || mesh.vertex_class(v) == VertexClass::Inner) {
        EXPECT_TRUE(same_point(mesh.point(v), before.point(v))) << v;
      }
    }
  }
}

TEST(OdtSmoothBoundary, SurfaceSmoothingDoesNotDependOnThreadCount) {
  // The surface vertices move by colours, each colour in parallel: the same
  // mesh with one thread and with two, and the faces stay on their planes.
  const int n = 20;  // about 200 surface vertices per colour, past the parallel threshold
  TetMesh start = build(testing::make_cube_mesh(n, 0.1, 7));
  ASSERT_GT(perturb_cube_boundary(start, n, 0.3, 11), 2000);
  const BoundaryGeometry geometry = cube_geometry(true);
  TetMesh one = start, two = start;
  const OdtSmoothReport r1 = testing::with_threads(1, [&] { return odt_smooth_surface(one, geometry); });
  const OdtSmoothReport r2 = testing::with_threads(2, [&] { return odt_smooth_surface(two, geometry); });
  std::printf("cube n = %d: surface moved %zu / %zu, refused %zu / %zu, halvings %zu / %zu\n", n, r1.moved, r2.moved,
              r1.refused, r2.refused, r1.halvings, r2.halvings);
  EXPECT_GT(r1.moved, 2000u);
  EXPECT_EQ(r1.moved, r2.moved);
  EXPECT_EQ(r1.refused, r2.refused);
  EXPECT_EQ(r1.halvings, r2.halvings);
  std::size_t differing = 0;
  for (index_t v = 0; v < one.vertex_slots(); ++v) differing += !same_point(one.point(v), two.point(v));
  EXPECT_EQ(differing, 0u);
  expect_on_cube(two);
  expect_valid(two, 1.0);
}

TEST(OdtSmoothBoundary, QualityGuardReadsCurrentBallMinima) {
  // The guard reads each ball's minimum stretch from stretches kept per tet
  // and updated by the moves: every minimum it reads equals the one
  // computed from the mesh, over several sweeps in both thread counts, and
  // checking changes nothing.
  const int n = 12;
  TetMesh start = build(testing::make_cube_mesh(n, 0.1, 7));
  ASSERT_GT(perturb_cube_boundary(start, n, 0.3, 11), 500);
  const BoundaryGeometry geometry = cube_geometry(true);
  BoundarySmoothOptions checked;
  checked.iterations = 4;
  checked.check_stretch_cache = true;
  BoundarySmoothOptions plain = checked;
  plain.check_stretch_cache = false;
  for (const int threads : {1, 2}) {
    TetMesh with_check = start, without = start;
    const OdtSmoothReport r =
        testing::with_threads(threads, [&] { return odt_smooth_surface(with_check, geometry, checked); });
    testing::with_threads(threads, [&] { return odt_smooth_surface(without, geometry, plain); });
    std::printf("%d thread(s): %zu ball minima read, %zu differ; %zu moves in %d sweeps\n", threads, r.cache_checked,
                r.cache_disagreements, r.moved, r.sweeps);
    EXPECT_GE(r.sweeps, 2);
    EXPECT_GT(r.moved, r.cache_checked / 4);  // many moves change the kept stretches
    EXPECT_GT(r.cache_checked, 1000u);
    EXPECT_EQ(r.cache_disagreements, 0u);
    std::size_t differing = 0;
    for (index_t v = 0; v < start.vertex_slots(); ++v)
      differing += !same_point(with_check.point(v), without.point(v));
    EXPECT_EQ(differing, 0u);
  }
}

TEST(OdtSmoothBoundary, MaskedOutVerticesStay) {
  const int n = 5;
  TetMesh mesh = build(testing::make_cube_mesh(n, 0.1, 3));
  ASSERT_GT(perturb_cube_boundary(mesh, n, 0.3, 5), 50);
  const BoundaryGeometry geometry = cube_geometry(true);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) mask[v] = mesh.point(v).x() < 0.5;
  const TetMesh before = mesh;
  OdtSmoothReport rc, rs;
  run_phases(mesh, geometry, 3, &rc, &rs, mask);
  SurfaceFlipOptions fo;
  fo.vertex_mask = mask;
  flip_surface_edges(mesh, geometry, fo);
  std::size_t moved_in = 0;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    if (!before.vertex_alive(v)) continue;
    if (!mask[v]) {
      EXPECT_TRUE(same_point(mesh.point(v), before.point(v))) << v;
    }
    moved_in += mask[v] && !same_point(mesh.point(v), before.point(v));
  }
  EXPECT_GT(moved_in, 10u);
  // Every boundary triangle with a masked-out vertex is unchanged.
  std::vector<std::array<index_t, 3>> frozen_before, frozen_after;
  for (const TetMesh* m : {&before, static_cast<const TetMesh*>(&mesh)}) {
    auto& list = m == &before ? frozen_before : frozen_after;
    for (const BoundaryFace& f : boundary_faces(*m)) {
      if (mask[f.v[0]] && mask[f.v[1]] && mask[f.v[2]]) continue;
      std::array<index_t, 3> s{{f.v[0], f.v[1], f.v[2]}};
      std::sort(s.begin(), s.end());
      list.push_back(s);
    }
    std::sort(list.begin(), list.end());
  }
  EXPECT_EQ(frozen_before, frozen_after);
  expect_on_cube(mesh);
  expect_valid(mesh, 1.0);
}

TEST(OdtSmoothBoundary, CylinderVerticesStayOnTheCylinderAndCircles) {
  Annulus an = make_annulus();
  const GridMesh gm = make_grid_mesh(an.grid);
  TetMesh mesh = build(gm.mesh);
  const double volume = mesh_volume(mesh);
  ASSERT_GT(perturb_boundary(mesh, an.grid, gm, 0.35, 3), 200);
  const auto cylinders = [](index_t r) { return r < 2; };
  const auto caps = [](index_t r) { return r >= 2; };
  const AngleStats c0 = angle_stats(mesh, cylinders), p0 = angle_stats(mesh, caps);
  const int nd0 = non_delaunay_edges(mesh, cylinders);
  OdtSmoothReport rc, rs;
  run_phases(mesh, an.geometry, 5, &rc, &rs);
  const AngleStats c1 = angle_stats(mesh, cylinders), p1 = angle_stats(mesh, caps);
  const int nd1 = non_delaunay_edges(mesh, cylinders);

  // Radius and height of every cylinder, cap and circle vertex.
  double radius_dev = 0, height_dev = 0, circle_dev = 0;
  for (const BoundaryFace& f : boundary_faces(mesh))
    for (index_t v : f.v) {
      const Vec3& p = mesh.point(v);
      const double rho = std::hypot(p.x(), p.y());
      if (f.region < 2) radius_dev = std::max(radius_dev, std::abs(rho / (f.region ? an.r_out : an.r_in) - 1));
      else height_dev = std::max(height_dev, std::abs(p.z() - (f.region - 2) * an.height));
      if (mesh.vertex_class(v) == VertexClass::Curve) {
        const double r = std::abs(rho - an.r_in) < std::abs(rho - an.r_out) ? an.r_in : an.r_out;
        const double z = p.z() < an.height / 2 ? 0 : an.height;
        circle_dev = std::max({circle_dev, std::abs(rho / r - 1), std::abs(p.z() - z)});
      }
    }
  std::printf("annulus: cylinder triangles min angle %.2f -> %.2f deg, mean min %.2f -> %.2f; caps min %.2f -> %.2f, "
              "mean %.2f -> %.2f; non-Delaunay cylinder edges %d -> %d; radius dev %.1e, circle dev %.1e, "
              "cap height dev %.1e; curves moved %zu, surface moved %zu refused %zu\n",
              c0.min, c1.min, c0.mean, c1.mean, p0.min, p1.min, p0.mean, p1.mean, nd0, nd1, radius_dev, circle_dev,
              height_dev, rc.moved, rs.moved, rs.refused);
  EXPECT_LE(radius_dev, 1e-12);
  EXPECT_LE(circle_dev, 1e-12);
  EXPECT_LE(height_dev, 1e-12);
  EXPECT_GT(c1.min, c0.min + 1);
  EXPECT_GT(c1.mean, c0.mean + 1);
  EXPECT_GT(p1.mean, p0.mean + 1);
  EXPECT_GT(rc.moved, 0u);
  // No shrinkage: the volume stays that of the inscribed polyhedral annulus.
  expect_valid(mesh, 0);
  EXPECT_NEAR(mesh_volume(mesh), volume, 2e-3 * volume);
  EXPECT_LE(max_surface_distance(mesh, an.geometry, an.r_out), 1e-12);
}

TEST(OdtSmoothBoundary, CircleSmoothingSpreadsAngles) {
  // Only the circle vertices are perturbed (in angle); Eq. 2.34 on the
  // central angle brings back even spacing without leaving the circle.
  Annulus an = make_annulus();
  const GridMesh gm = make_grid_mesh(an.grid);
  TetMesh mesh = build(gm.mesh);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  const double dt = 2 * kPi / an.grid.n[1];
  auto spacing = [&](const TetMesh& m) {  // min and max angle gap on the outer bottom circle
    std::vector<double> t;
    for (index_t v = 0; v < m.vertex_slots(); ++v)
      if (gm.ijk[v][0] == an.grid.n[0] && gm.ijk[v][2] == 0) t.push_back(std::atan2(m.point(v).y(), m.point(v).x()));
    std::sort(t.begin(), t.end());
    double lo = 10, hi = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double gap = i + 1 < t.size() ? t[i + 1] - t[i] : t[0] + 2 * kPi - t[i];
      lo = std::min(lo, gap), hi = std::max(hi, gap);
    }
    return std::make_pair(lo / dt, hi / dt);
  };
  for (index_t v = 0; v < mesh.vertex_slots(); ++v)
    if (mesh.vertex_class(v) == VertexClass::Curve)
      mesh.move_vertex(v, an.grid.map(gm.ijk[v][0], gm.ijk[v][1] + u(rng), gm.ijk[v][2]));
  const auto s0 = spacing(mesh);
  BoundarySmoothOptions options;
  options.iterations = 20;
  options.quality_guard = false;
  const OdtSmoothReport r = odt_smooth_curves(mesh, an.geometry, options);
  const auto s1 = spacing(mesh);
  std::printf("circle: angle gaps / (2 pi / n) [%.3f, %.3f] -> [%.3f, %.3f] after %d sweeps (%zu moves)\n", s0.first,
              s0.second, s1.first, s1.second, r.sweeps, r.moved);
  EXPECT_GT(s1.first, s0.first);
  EXPECT_LT(s1.second, s0.second);
  EXPECT_GT(s1.first, 0.8);
  EXPECT_LT(s1.second, 1.2);
  EXPECT_LE(max_surface_distance(mesh, an.geometry, an.r_out), 1e-12);
  expect_valid(mesh, 0);
}

// ---- a spherical shell sector: spheres, cones, planes, circles, lines ---------------

TEST(OdtSmoothBoundary, SphereAndConeSectorStaysOnItsSurfaces) {
  Grid grid;
  grid.n = {{4, 8, 12}};
  const double r0 = 1, r1 = 1.5, t0 = 40 / kDeg, t1 = 80 / kDeg, p1 = 90 / kDeg;
  const auto n = grid.n;
  grid.map = [=](double i, double j, double k) {
    const double r = r0 + i * (r1 - r0) / n[0], t = t0 + j * (t1 - t0) / n[1], p = k * p1 / n[2];
    return Vec3(r * std::sin(t) * std::cos(p), r * std::sin(t) * std::sin(p), r * std::cos(t));
  };
  grid.region[0][0] = 0, grid.region[0][1] = 1;  // spheres r0, r1
  grid.region[1][0] = 2, grid.region[1][1] = 3;  // cones t0, t1
  grid.region[2][0] = 4, grid.region[2][1] = 5;  // planes y = 0, x = 0
  BoundaryGeometry g;
  const Vec3 o = Vec3::Zero(), z = Vec3::UnitZ();
  g.regions = {sphere(o, r0), sphere(o, r1), cone(o, z, t0), cone(o, z, t1), plane(o, Vec3::UnitY()),
               plane(o, Vec3::UnitX())};
  const double radii[2] = {r0, r1}, polar[2] = {t0, t1};
  for (int s = 0; s < 2; ++s)
    for (int c = 0; c < 2; ++c) {  // sphere x cone: circles of latitude
      g.curves.push_back(circle_curve(radii[s] * std::cos(polar[c]) * z, z, radii[s] * std::sin(polar[c])));
      g.curve_regions.push_back({{s, 2 + c}});
    }
  for (int s = 0; s < 2; ++s) {  // sphere x plane: great circles
    g.curves.push_back(circle_curve(o, Vec3::UnitY(), radii[s]));
    g.curve_regions.push_back({{s, 4}});
    g.curves.push_back(circle_curve(o, Vec3::UnitX(), radii[s]));
    g.curve_regions.push_back({{s, 5}});
  }
  for (int c = 0; c < 2; ++c) {  // cone x plane: lines through the apex
    g.curves.push_back(line_curve(o, Vec3(std::sin(polar[c]), 0, std::cos(polar[c]))));
    g.curve_regions.push_back({{2 + c, 4}});
    g.curves.push_back(line_curve(o, Vec3(0, std::sin(polar[c]), std::cos(polar[c]))));
    g.curve_regions.push_back({{2 + c, 5}});
  }
  const GridMesh gm = make_grid_mesh(grid);
  TetMesh mesh = build(gm.mesh);
  ASSERT_LE(max_surface_distance(mesh, g, r1), 1e-15);
  ASSERT_GT(perturb_boundary(mesh, grid, gm, 0.35, 21), 200);
  ASSERT_LE(max_surface_distance(mesh, g, r1), 1e-15);
  const TetMesh before = mesh;
  const auto spheres = [](index_t r) { return r < 2; };
  const auto cones = [](index_t r) { return r == 2 || r == 3; };
  const auto planes = [](index_t r) { return r >= 4; };
  const AngleStats s0 = angle_stats(mesh, spheres), c0 = angle_stats(mesh, cones), q0 = angle_stats(mesh, planes);
  OdtSmoothReport rc, rs;
  run_phases(mesh, g, 5, &rc, &rs);
  const AngleStats s1 = angle_stats(mesh, spheres), c1 = angle_stats(mesh, cones), q1 = angle_stats(mesh, planes);
  const double dev = max_surface_distance(mesh, g, r1);
  std::printf("sphere/cone sector: spheres min %.2f -> %.2f mean %.2f -> %.2f; cones min %.2f -> %.2f mean %.2f -> "
              "%.2f; planes min %.2f -> %.2f mean %.2f -> %.2f; surface deviation %.1e; curves moved %zu, surface "
              "moved %zu refused %zu\n",
              s0.min, s1.min, s0.mean, s1.mean, c0.min, c1.min, c0.mean, c1.mean, q0.min, q1.min, q0.mean, q1.mean,
              dev, rc.moved, rs.moved, rs.refused);
  EXPECT_LE(dev, 1e-12);
  EXPECT_GT(s1.mean, s0.mean + 1);
  EXPECT_GT(c1.mean, c0.mean + 1);
  EXPECT_GT(q1.mean, q0.mean + 1);
  EXPECT_GT(std::min({s1.min, c1.min, q1.min}), std::min({s0.min, c0.min, q0.min}));
  for (index_t v = 0; v < mesh.vertex_slots(); ++v)
    if (mesh.vertex_class(v) == VertexClass::Corner || mesh.vertex_class(v) == VertexClass::Inner) {
      EXPECT_TRUE(same_point(mesh.point(v), before.point(v))) << v;
    }
  expect_valid(mesh, 0);
}

// ---- a toroidal shell: two tori, no curves --------------------------------------------

TEST(OdtSmoothBoundary, TorusShellStaysOnItsTori) {
  Grid grid;
  grid.n = {{2, 24, 56}};
  grid.periodic = {{false, true, true}};
  const double R = 3, ra = 0.7, rb = 1.0;
  const auto n = grid.n;
  grid.map = [=](double i, double j, double k) {
    const double r = ra + i * (rb - ra) / n[0], phi = j * 2 * kPi / n[1], theta = k * 2 * kPi / n[2];
    const double rho = R + r * std::cos(phi);
    return Vec3(rho * std::cos(theta), rho * std::sin(theta), r * std::sin(phi));
  };
  grid.region[0][0] = 0, grid.region[0][1] = 1;
  BoundaryGeometry g;
  g.regions = {torus(Vec3::Zero(), Vec3::UnitZ(), R, ra), torus(Vec3::Zero(), Vec3::UnitZ(), R, rb)};
  const GridMesh gm = make_grid_mesh(grid);
  TetMesh mesh = build(gm.mesh);
  ASSERT_GT(perturb_boundary(mesh, grid, gm, 0.35, 4), 500);
  const AngleStats a0 = angle_stats(mesh);
  OdtSmoothReport rc, rs;
  run_phases(mesh, g, 5, &rc, &rs);
  const AngleStats a1 = angle_stats(mesh);
  const double dev = max_surface_distance(mesh, g, rb);
  std::printf("torus shell: min angle %.2f -> %.2f, mean %.2f -> %.2f; surface deviation %.1e; moved %zu refused "
              "%zu\n",
              a0.min, a1.min, a0.mean, a1.mean, dev, rs.moved, rs.refused);
  EXPECT_EQ(rc.moved, 0u);  // no curves
  EXPECT_LE(dev, 1e-12);
  EXPECT_GT(a1.min, a0.min + 1);
  EXPECT_GT(a1.mean, a0.mean + 1);
  expect_valid(mesh, 0);
}

// ---- surface edge flips (Fig. 2.45) -----------------------------------------------------

TEST(FlipSurfaceEdges, PlanarNonDelaunayEdgeFlips) {
  // Two tets over the flat quad a c b d (z = 0) with apex e; the diagonal
  // (a, b) sees angles of about 147 degrees at c and d.
  testing::TestMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0.3, 0), Vec3(1, -0.3, 0), Vec3(1, 0, 1)};
  m.tets = {Tet{{0, 1, 2, 4}}, Tet{{0, 1, 3, 4}}};
  for (Tet& t : m.tets) {
    const auto& p = m.points;
    if ((p[t[1]] - p[t[0]]).dot((p[t[2]] - p[t[0]]).cross(p[t[3]] - p[t[0]])) < 0) std::swap(t[1], t[2]);
  }
  // Region 0: the plane z = 0; the four side faces regions 1-4 (unfitted).
  m.face_regions.assign(2, Tet{{-1, -1, -1, -1}});
  int side = 1;
  for (std::size_t t = 0; t < 2; ++t)
    for (int f = 0; f < 4; ++f) {
      if (m.tets[t][f] == 4) m.face_regions[t][f] = 0;
      else if (m.tets[t][f] != 0 && m.tets[t][f] != 1) continue;  // the shared face (a, b, e)
      else m.face_regions[t][f] = side++;
    }
  TetMesh mesh = build(m);
  BoundaryGeometry g;
  g.regions.resize(5);
  g.regions[0] = plane(Vec3::Zero(), Vec3::UnitZ());
  const double volume = mesh_volume(mesh);
  ASSERT_TRUE(mesh.has_edge(0, 1));
  const SurfaceFlipStats s = flip_surface_edges(mesh, g);
  EXPECT_EQ(s.flips, 1u);
  EXPECT_FALSE(mesh.has_edge(0, 1));
  EXPECT_TRUE(mesh.has_edge(2, 3));
  EXPECT_EQ(non_delaunay_edges(mesh), 0);
  expect_valid(mesh, volume);
  // Already Delaunay: nothing more to flip.
  EXPECT_EQ(flip_surface_edges(mesh, g).flips, 0u);
}

TEST(FlipSurfaceEdges, CylinderFlipsKeepVerticesOnTheSurface) {
  Annulus an = make_annulus();
  const GridMesh gm = make_grid_mesh(an.grid);
  TetMesh mesh = build(gm.mesh);
  ASSERT_GT(perturb_boundary(mesh, an.grid, gm, 0.35, 3), 200);
  const auto cylinders = [](index_t r) { return r < 2; };
  const int nd0 = non_delaunay_edges(mesh, cylinders), all0 = non_delaunay_edges(mesh);
  const AngleStats a0 = angle_stats(mesh);
  const SurfaceFlipStats s = flip_surface_edges(mesh, an.geometry);
  const int nd1 = non_delaunay_edges(mesh, cylinders), all1 = non_delaunay_edges(mesh);
  const AngleStats a1 = angle_stats(mesh);
  std::printf("annulus flips: %zu flipped, %zu refused; non-Delaunay edges cylinders %d -> %d, all %d -> %d; min "
              "angle %.2f -> %.2f, mean %.2f -> %.2f\n",
              s.flips, s.refused, nd0, nd1, all0, all1, a0.min, a1.min, a0.mean, a1.mean);
  EXPECT_GT(s.flips, 0u);
  EXPECT_LT(nd1, nd0);
  EXPECT_LT(all1, all0);
  EXPECT_GE(a1.min, a0.min);
  EXPECT_LE(max_surface_distance(mesh, an.geometry, an.r_out), 1e-15);
  expect_valid(mesh, 0);
}

TEST(FlipSurfaceEdges, SmoothingAndFlipsTogether) {
  // Phase (2) as the orchestrator runs it: smoothing, then flips, repeated.
  Annulus an = make_annulus();
  const GridMesh gm = make_grid_mesh(an.grid);
  TetMesh mesh = build(gm.mesh);
  ASSERT_GT(perturb_boundary(mesh, an.grid, gm, 0.35, 3), 200);
  const AngleStats a0 = angle_stats(mesh);
  const int nd0 = non_delaunay_edges(mesh);
  std::size_t flips = 0;
  for (int round = 0; round < 3; ++round) {
    odt_smooth_curves(mesh, an.geometry);
    odt_smooth_surface(mesh, an.geometry);
    flips += flip_surface_edges(mesh, an.geometry).flips;
  }
  const AngleStats a1 = angle_stats(mesh);
  const int nd1 = non_delaunay_edges(mesh);
  std::printf("annulus smoothing + flips x3: %zu flips; min angle %.2f -> %.2f, mean %.2f -> %.2f; non-Delaunay "
              "edges %d -> %d\n",
              flips, a0.min, a1.min, a0.mean, a1.mean, nd0, nd1);
  EXPECT_GT(a1.min, a0.min + 10);
  EXPECT_GT(a1.mean, a0.mean + 3);
  EXPECT_LT(nd1, nd0 / 2);
  EXPECT_LE(max_surface_distance(mesh, an.geometry, an.r_out), 1e-12);
  expect_valid(mesh, 0);
}

}  // namespace
}  // namespace femorph
