// SurfaceMesh (build_surface_mesh, extract_boundary_surface): adjacency on
// hand-built surfaces against a brute-force search, refused inputs with their
// counts, and the boundary of tet meshes: closed, outward, the right size.
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace femorph {
namespace {

// The unit cube, two triangles per face, counter-clockwise from outside.
void unit_cube(std::vector<Vec3>& points, std::vector<Tri>& triangles) {
  points.clear();
  for (int k = 0; k < 8; ++k) points.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  triangles = {{0, 2, 3}, {0, 3, 1},   // z = 0, normal -z
               {4, 5, 7}, {4, 7, 6},   // z = 1
               {0, 1, 5}, {0, 5, 4},   // y = 0
               {2, 6, 7}, {2, 7, 3},   // y = 1
               {0, 4, 6}, {0, 6, 2},   // x = 0
               {1, 3, 7}, {1, 7, 5}};  // x = 1
}

// Brute force: the triangle other than f holding both ends of edge k of f,
// -1 if none, -2 if several.
index_t brute_neighbour(const std::vector<Tri>& triangles, index_t f, int k) {
  const index_t a = triangles[f][k], b = triangles[f][(k + 1) % 3];
  index_t found = -1;
  for (index_t g = 0; g < static_cast<index_t>(triangles.size()); ++g) {
    if (g == f) continue;
    const Tri& t = triangles[g];
    if (std::count(t.begin(), t.end(), a) && std::count(t.begin(), t.end(), b)) found = found == -1 ? g : -2;
  }
  return found;
}

// Adjacency is its own inverse and agrees with the brute-force search; the
// vertex-triangle lists hold exactly the triangles using the vertex.
void expect_consistent(const SurfaceMesh& s) {
  for (index_t f = 0; f < s.num_triangles(); ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t g = s.neighbors[f][k];
      EXPECT_EQ(g, brute_neighbour(s.triangles, f, k)) << "triangle " << f << " edge " << k;
      if (g < 0) continue;
      const index_t a = s.triangles[f][k], b = s.triangles[f][(k + 1) % 3];
      int back = -1;
      for (int q = 0; q < 3; ++q)
        if (s.triangles[g][q] == b && s.triangles[g][(q + 1) % 3] == a) back = q;
      ASSERT_GE(back, 0) << "neighbour does not run the edge the other way";
      EXPECT_EQ(s.neighbors[g][back], f);
    }
  ASSERT_EQ(s.vertex_offsets.size(), s.points.size() + 1);
  for (index_t v = 0; v < s.num_points(); ++v) {
    std::vector<index_t> expected;
    for (index_t f = 0; f < s.num_triangles(); ++f)
      if (std::count(s.triangles[f].begin(), s.triangles[f].end(), v)) expected.push_back(f);
    const std::vector<index_t> got(s.vertex_triangles.begin() + s.vertex_offsets[v],
                                   s.vertex_triangles.begin() + s.vertex_offsets[v + 1]);
    EXPECT_EQ(got, expected) << "vertex " << v;
  }
}

// Sum of area * normal (0 on a closed surface) and the enclosed volume by the
// divergence theorem.
void closure_and_volume(const SurfaceMesh& s, Vec3& area_vector, double& volume) {
  area_vector.setZero();
  volume = 0;
  for (index_t f = 0; f < s.num_triangles(); ++f) {
    area_vector += s.areas[f] * s.normals[f];
    volume += s.points[s.triangles[f][0]].dot(s.normals[f]) * s.areas[f] / 3.0;
  }
}

TEST(SurfaceMesh, CubeByHand) {
  std::vector<Vec3> points;
  std::vector<Tri> triangles;
  unit_cube(points, triangles);
  SurfaceMesh s;
  SurfaceReport report;
  const Status st = build_surface_mesh(points, triangles, s, false, &report);
  ASSERT_TRUE(st.ok) << st.message;
  EXPECT_EQ(s.num_points(), 8);
  EXPECT_EQ(s.num_triangles(), 12);
  EXPECT_EQ(report.open_edges + report.nonmanifold_edges + report.misoriented_edges + report.degenerate_triangles, 0u);
  expect_consistent(s);
  // Exact neighbours of the first bottom triangle (0, 2, 3): across (0, 2)
  // the x = 0 face's (0, 6, 2), across (2, 3) the y = 1 face's (2, 7, 3),
  // across (3, 0) the other bottom triangle.
  EXPECT_EQ(s.neighbors[0], (Tri{{9, 7, 1}}));
  for (index_t f = 0; f < 12; ++f) {
    EXPECT_DOUBLE_EQ(s.areas[f], 0.5);
    EXPECT_NEAR(s.normals[f].norm(), 1.0, 1e-15);
  }
  EXPECT_TRUE(s.normals[0].isApprox(Vec3(0, 0, -1)));
  EXPECT_TRUE(s.normals[2].isApprox(Vec3(0, 0, 1)));
  EXPECT_TRUE(s.normals[10].isApprox(Vec3(1, 0, 0)));
  EXPECT_NEAR(s.mean_edge_length, (12 + 6 * std::sqrt(2.0)) / 18, 1e-15);
  Vec3 area_vector;
  double volume;
  closure_and_volume(s, area_vector, volume);
  EXPECT_LT(area_vector.norm(), 1e-15);
  EXPECT_NEAR(volume, 1.0, 1e-15);
  EXPECT_TRUE(s.source_vertex.empty());
  EXPECT_TRUE(s.source_face.empty());
}

TEST(SurfaceMesh, ScaleInvariant) {
  std::vector<Vec3> points;
  std::vector<Tri> triangles;
  unit_cube(points, triangles);
  SurfaceMesh unit;
  ASSERT_TRUE(build_surface_mesh(points, triangles, unit).ok);
  for (double scale : {1e-8, 1e8}) {
    std::vector<Vec3> scaled = points;
    for (Vec3& p : scaled) p = p * scale + Vec3(3, -1, 2) * scale;
    SurfaceMesh s;
    SurfaceReport report;
    ASSERT_TRUE(build_surface_mesh(scaled, triangles, s, false, &report).ok) << scale;
    EXPECT_EQ(report.degenerate_triangles, 0u);
    EXPECT_EQ(s.neighbors, unit.neighbors);
    for (index_t f = 0; f < 12; ++f) {
      EXPECT_TRUE(s.normals[f].isApprox(unit.normals[f], 1e-12));
      EXPECT_NEAR(s.areas[f] / (scale * scale), 0.5, 1e-12);
    }
    EXPECT_NEAR(s.mean_edge_length / scale, unit.mean_edge_length, 1e-12);
  }
}

TEST(SurfaceMesh, OpenSurfaceRefusedUnlessAllowed) {
  std::vector<Vec3> points;
  std::vector<Tri> triangles;
  unit_cube(points, triangles);
  triangles.pop_back();  // a hole: three open edges
  SurfaceMesh s;
  SurfaceReport report;
  Status st = build_surface_mesh(points, triangles, s, false, &report);
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("3 open edges"), std::string::npos) << st.message;
  EXPECT_EQ(report.open_edges, 3u);
  EXPECT_EQ(report.nonmanifold_edges, 0u);
  EXPECT_TRUE(s.triangles.empty());

  st = build_surface_mesh(points, triangles, s, true, &report);
  ASSERT_TRUE(st.ok) << st.message;
  EXPECT_EQ(report.open_edges, 3u);
  int open = 0;
  for (const Tri& n : s.neighbors) open += static_cast<int>(std::count(n.begin(), n.end(), kInvalidIndex));
  EXPECT_EQ(open, 3);
  expect_consistent(s);
}

TEST(SurfaceMesh, NonManifoldEdgeRefused) {
  std::vector<Vec3> points;
  std::vector<Tri> triangles;
  unit_cube(points, triangles);
  // A fin on edge (0, 1): that edge gets three triangles, the fin's other two
  // edges are open.
  points.emplace_back(0.5, -1, -1);
  triangles.push_back({0, 1, 8});
  for (bool allow_open : {false, true}) {
    SurfaceMesh s;
    SurfaceReport report;
    const Status st = build_surface_mesh(points, triangles, s, allow_open, &report);
    EXPECT_FALSE(st.ok);
    EXPECT_NE(st.message.find("1 non-manifold"), std::string::npos) << st.message;
    EXPECT_EQ(report.nonmanifold_edges, 1u);
    EXPECT_EQ(report.open_edges, 2u);
    EXPECT_EQ(st.message.find("open edges") != std::string::npos, !allow_open) << st.message;
  }
}

TEST(SurfaceMesh, InconsistentOrientationRefused) {
  std::vector<Vec3> points;
  std::vector<Tri> triangles;
  unit_cube(points, triangles);
  std::swap(triangles[4][1], triangles[4][2]);
  SurfaceMesh s;
  SurfaceReport report;
  const Status st = build_surface_mesh(points, triangles, s, false, &report);
  EXPECT_FALSE(st.ok);
  EXPECT_EQ(report.misoriented_edges, 3u);
  EXPECT_NE(st.message.find("3 edges whose two triangles are oriented inconsistently"), std::string::npos)
      << st.message;
}

TEST(SurfaceMesh, BadInputRefused) {
  std::vector<Vec3> points;
  std::vector<Tri> triangles;
  unit_cube(points, triangles);
  SurfaceMesh s;
  std::vector<Tri> bad = triangles;
  bad[3][1] = 8;
  EXPECT_FALSE(build_surface_mesh(points, bad, s).ok);
  bad = triangles;
  bad[3][1] = bad[3][0];
  EXPECT_FALSE(build_surface_mesh(points, bad, s).ok);
  std::vector<Vec3> nan_points = points;
  nan_points[5].x() = std::nan("");
  EXPECT_FALSE(build_surface_mesh(nan_points, triangles, s).ok);
}

TEST(SurfaceMesh, DegenerateTrianglesCounted) {
  // A zero-area triangle (2 is the midpoint of 0-1) beside a sound one.
  const std::vector<Vec3> points = {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  const std::vector<Tri> triangles = {{0, 1, 2}, {0, 2, 3}};
  SurfaceMesh s;
  SurfaceReport report;
  ASSERT_TRUE(build_surface_mesh(points, triangles, s, true, &report).ok);
  EXPECT_EQ(report.degenerate_triangles, 1u);
  EXPECT_EQ(s.normals[0], Vec3::Zero());
  EXPECT_EQ(s.areas[0], 0.0);
  EXPECT_TRUE(s.normals[1].isApprox(Vec3(0, 0, 1)));
}

TEST(ExtractBoundarySurface, TwoTets) {
  // Two positive tets sharing face (1, 2, 3): six boundary triangles.
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  const std::vector<Tet> tets = {{0, 1, 2, 3}, {1, 4, 2, 3}};
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(points, tets).ok);
  ASSERT_GT(mesh.orientation(1), 0);
  SurfaceMesh s;
  SurfaceReport report;
  const Status st = extract_boundary_surface(mesh, s, &report);
  ASSERT_TRUE(st.ok) << st.message;
  EXPECT_EQ(s.num_points(), 5);
  EXPECT_EQ(s.num_triangles(), 6);
  EXPECT_EQ(s.source_vertex, (std::vector<index_t>{0, 1, 2, 3, 4}));
  expect_consistent(s);
  for (index_t f = 0; f < 6; ++f) {
    const index_t t = s.source_face[f] / 4;
    const int lf = s.source_face[f] % 4;
    ASSERT_TRUE(mesh.is_boundary_face(t, lf));
    EXPECT_NE(lf, t == 0 ? 0 : 1) << "the shared face is interior";
    for (int k = 0; k < 3; ++k) EXPECT_EQ(s.source_vertex[s.triangles[f][k]], mesh.tet(t)[kTetFace[lf][k]]);
  }
  for (const Tri& n : s.neighbors) EXPECT_EQ(std::count(n.begin(), n.end(), kInvalidIndex), 0);
  Vec3 area_vector;
  double volume;
  closure_and_volume(s, area_vector, volume);
  EXPECT_LT(area_vector.norm(), 1e-15);
  EXPECT_NEAR(volume, testing::total_volume(points, tets), 1e-15);
}

TEST(ExtractBoundarySurface, JitteredCubeIsClosedAndOutward) {
  const testing::TestMesh cube = testing::make_cube_mesh(5, 0.1, 3);
  TetMesh mesh;
  BuildReport build_report;
  ASSERT_TRUE(mesh.build(cube.points, cube.tets, {}, &build_report).ok);
  SurfaceMesh s;
  ASSERT_TRUE(extract_boundary_surface(mesh, s).ok);
  EXPECT_EQ(static_cast<std::size_t>(s.num_triangles()), build_report.boundary_faces);
  EXPECT_EQ(s.num_triangles(), 6 * 5 * 5 * 2);
  EXPECT_EQ(s.num_points(), 6 * 6 * 6 - 4 * 4 * 4);
  EXPECT_TRUE(std::is_sorted(s.source_vertex.begin(), s.source_vertex.end()));
  for (index_t v = 0; v < s.num_points(); ++v) EXPECT_EQ(s.points[v], mesh.point(s.source_vertex[v]));
  for (index_t f = 0; f < s.num_triangles(); ++f) {
    const index_t t = s.source_face[f] / 4;
    const int lf = s.source_face[f] % 4;
    ASSERT_TRUE(mesh.is_boundary_face(t, lf));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(s.source_vertex[s.triangles[f][k]], mesh.tet(t)[kTetFace[lf][k]]);
  }
  expect_consistent(s);
  Vec3 area_vector;
  double volume;
  closure_and_volume(s, area_vector, volume);
  EXPECT_LT(area_vector.norm(), 1e-13);
  EXPECT_NEAR(volume, testing::total_volume(cube.points, cube.tets), 1e-13);
  EXPECT_NEAR(volume, 1.0, 1e-13);
  // Outward: on x = 1 every normal is +x.
  for (index_t f = 0; f < s.num_triangles(); ++f) {
    bool on_x1 = true;
    for (index_t v : s.triangles[f]) on_x1 = on_x1 && s.points[v].x() == 1.0;
    if (on_x1) {
      EXPECT_GT(s.normals[f].x(), 1 - 1e-12);
    }
  }
}

TEST(ExtractBoundarySurface, AfterLocalOperations) {
  // Tombstoned tets and vertices are skipped; new vertices are numbered in.
  const testing::TestMesh cube = testing::make_cube_mesh(3, 0.0, 1);
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(cube.points, cube.tets).ok);
  // Split a boundary edge on z = 0 (two boundary triangles become four) and
  // collapse an inner vertex away.
  index_t a = -1, b = -1, inner = -1;
  for (index_t t = 0; t < mesh.tet_slots() && a < 0; ++t)
    for (int f = 0; f < 4 && a < 0; ++f)
      if (mesh.is_boundary_face(t, f) && mesh.point(mesh.tet(t)[kTetFace[f][0]]).z() == 0 &&
          mesh.point(mesh.tet(t)[kTetFace[f][1]]).z() == 0 && mesh.point(mesh.tet(t)[kTetFace[f][2]]).z() == 0) {
        a = mesh.tet(t)[kTetFace[f][0]];
        b = mesh.tet(t)[kTetFace[f][1]];
      }
  ASSERT_GE(a, 0);
  index_t added = -1;
  ASSERT_EQ(mesh.split_edge(a, b, nullptr, &added), OpStatus::Ok);
  for (index_t v = 0; v < mesh.vertex_slots() && inner < 0; ++v)
    if (mesh.vertex_alive(v) && mesh.vertex_class(v) == VertexClass::Inner) inner = v;
  ASSERT_GE(inner, 0);
  std::vector<index_t> around;
  mesh.vertex_neighbors(inner, around);
  bool collapsed = false;
  for (index_t w : around) {
    if (mesh.half_edge_collapse(Keep{w}, Remove{inner}) == OpStatus::Ok) {
      collapsed = true;
      break;
    }
  }
  ASSERT_TRUE(collapsed);
  ASSERT_LT(mesh.live_tets(), static_cast<std::size_t>(mesh.tet_slots()));  // tombstones exist

  SurfaceMesh s;
  ASSERT_TRUE(extract_boundary_surface(mesh, s).ok);
  EXPECT_EQ(s.num_triangles(), 6 * 3 * 3 * 2 + 2);
  EXPECT_EQ(s.num_points(), 4 * 4 * 4 - 2 * 2 * 2 + 1);
  EXPECT_NE(std::find(s.source_vertex.begin(), s.source_vertex.end(), added), s.source_vertex.end());
  for (index_t f = 0; f < s.num_triangles(); ++f) EXPECT_TRUE(mesh.tet_alive(s.source_face[f] / 4));
  Vec3 area_vector;
  double volume;
  closure_and_volume(s, area_vector, volume);
  EXPECT_LT(area_vector.norm(), 1e-13);
  EXPECT_NEAR(volume, 1.0, 1e-13);
}

}  // namespace
}  // namespace femorph
