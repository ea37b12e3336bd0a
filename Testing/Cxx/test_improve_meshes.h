// Meshes of curved parts for the Improve tests, built at run time: a
// structured grid in curvilinear coordinates (cylinders, cones, spheres,
// tori as grid faces) and an annulus with its fitted geometry.
#pragma once

#include "common/types.h"
#include "geometry/curve_primitive.h"
#include "improve/boundary_geometry.h"
#include "mesh/tet_mesh.h"
#include "test_meshes.h"
#include "test_surfaces.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace femorph {
namespace testing {
namespace improve_meshes {

using test_surfaces::cylinder;
using test_surfaces::plane;

/// The TetMesh of a test mesh, with its face regions.
inline TetMesh build(const TestMesh& m) {
  TetMesh mesh;
  BuildOptions options;
  options.face_regions = m.face_regions;
  const Status status = mesh.build(m.points, m.tets, options);
  EXPECT_TRUE(status.ok) << status.message;
  return mesh;
}

inline CurvePrimitive line_curve(const Vec3& start, const Vec3& end) {
  CurvePrimitive c;
  c.type = CurveType::Line;
  c.start = start;
  c.end = end;
  c.direction = (end - start).normalized();
  return c;
}

inline CurvePrimitive circle_curve(const Vec3& center, const Vec3& normal, double radius) {
  CurvePrimitive c;
  c.type = CurveType::Circle;
  c.center = center;
  c.normal = normal.normalized();
  c.radius = radius;
  return c;
}

// ---- structured meshes in curvilinear coordinates ---------------------------

/// A grid of n[0] x n[1] x n[2] cells in the coordinates (i, j, k), mapped to
/// space by `map` (taking fractional grid coordinates), each cell cut into 6
/// tets as in make_cube_mesh (Kuhn; conforming, also across a periodic seam).
/// Boundary faces on the plane i = 0 get region[0][0], i = n[0] region[0][1],
/// and so on; periodic axes have no boundary.
struct Grid {
  std::array<int, 3> n{{1, 1, 1}};
  std::array<bool, 3> periodic{{false, false, false}};
  std::function<Vec3(double, double, double)> map;
  int region[3][2] = {{-1, -1}, {-1, -1}, {-1, -1}};
};

struct GridMesh {
  TestMesh mesh;
  std::vector<std::array<int, 3>> ijk;  // grid coordinates per point
};

inline GridMesh make_grid_mesh(const Grid& g) {
  GridMesh out;
  std::array<int, 3> m;
  for (int a = 0; a < 3; ++a) m[a] = g.periodic[a] ? g.n[a] : g.n[a] + 1;
  auto id = [&](std::array<int, 3> c) {
    for (int a = 0; a < 3; ++a) c[a] = (c[a] % m[a] + m[a]) % m[a];
    return static_cast<index_t>((c[2] * m[1] + c[1]) * m[0] + c[0]);
  };
  for (int k = 0; k < m[2]; ++k)
    for (int j = 0; j < m[1]; ++j)
      for (int i = 0; i < m[0]; ++i) {
        out.mesh.points.push_back(g.map(i, j, k));
        out.ijk.push_back({{i, j, k}});
      }
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const auto& p = out.mesh.points;
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i)
        for (const auto& perm : perms) {
          std::array<int, 3> c{{i, j, k}};
          Tet t;
          t[0] = id(c);
          for (int s = 0; s < 3; ++s) {
            ++c[perm[s]];
            t[s + 1] = id(c);
          }
          if ((p[t[1]] - p[t[0]]).dot((p[t[2]] - p[t[0]]).cross(p[t[3]] - p[t[0]])) < 0) std::swap(t[1], t[2]);
          out.mesh.tets.push_back(t);
        }
  out.mesh.face_regions.assign(out.mesh.tets.size(), Tet{{-1, -1, -1, -1}});
  for (std::size_t t = 0; t < out.mesh.tets.size(); ++t)
    for (int f = 0; f < 4; ++f)
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2 && !g.periodic[a]; ++side) {
          bool all = true;
          for (int q = 0; q < 3; ++q) all = all && out.ijk[out.mesh.tets[t][kTetFace[f][q]]][a] == (side ? g.n[a] : 0);
          if (all) out.mesh.face_regions[t][f] = g.region[a][side];
        }
  return out;
}

// ---- an annulus: two cylinders, two planar caps, four circles ----------------------

struct Annulus {
  double r_in = 1, r_out = 2, height = 1;
  Grid grid;
  BoundaryGeometry geometry;
};

inline Annulus make_annulus() {
  Annulus a;
  a.grid.n = {{2, 24, 4}};
  a.grid.periodic = {{false, true, false}};
  const double r_in = a.r_in, r_out = a.r_out, height = a.height;
  const auto n = a.grid.n;
  a.grid.map = [=](double i, double j, double k) {
    const double r = r_in + i * (r_out - r_in) / n[0], t = j * 2 * kPi / n[1];
    return Vec3(r * std::cos(t), r * std::sin(t), k * height / n[2]);
  };
  a.grid.region[0][0] = 0;  // inner cylinder
  a.grid.region[0][1] = 1;  // outer cylinder
  a.grid.region[2][0] = 2;  // bottom cap
  a.grid.region[2][1] = 3;  // top cap
  const Vec3 z = Vec3::UnitZ();
  a.geometry.regions = {cylinder(Vec3::Zero(), z, r_in), cylinder(Vec3::Zero(), z, r_out), plane(Vec3::Zero(), z),
                        plane(height * z, z)};
  for (int cyl = 0; cyl < 2; ++cyl)
    for (int cap = 0; cap < 2; ++cap) {
      a.geometry.curves.push_back(circle_curve(cap * height * z, z, cyl ? r_out : r_in));
      a.geometry.curve_regions.push_back({{cyl, 2 + cap}});
    }
  return a;
}

}  // namespace improve_meshes
}  // namespace testing
}  // namespace femorph
