// The independent validity checker on hand-built meshes with known answers:
// every failing case asserts the exact counts it must produce.
#include "quality/check_validity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace femorph {
namespace {

struct Mesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
};

double volume6(const Mesh& m, const Tet& t) {
  const Vec3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
  return (b - a).dot((c - a).cross(d - a));
}

// Swaps two vertices of every negative tet (exact for the small integer and
// dyadic coordinates used here).
void orient_positive(Mesh& m) {
  for (Tet& t : m.tets)
    if (volume6(m, t) < 0) std::swap(t[2], t[3]);
}

ValidityReport check(const Mesh& m, const ValidityOptions& options = {}) {
  return check_validity(m.points, m.tets, options);
}

// Compares every problem count of a report with the expected ones, given by
// name; counts not named must be 0.
using Counts = std::map<std::string, std::size_t>;

void expect_counts(const ValidityReport& r, const Counts& expected) {
  const Counts actual = {{"index_out_of_range", r.index_out_of_range},
                         {"repeated_vertex", r.repeated_vertex},
                         {"nonfinite_points", r.nonfinite_points},
                         {"inverted", r.inverted},
                         {"degenerate", r.degenerate},
                         {"overshared_faces", r.overshared_faces},
                         {"orientation_mismatches", r.orientation_mismatches},
                         {"duplicate_tets", r.duplicate_tets},
                         {"nonmanifold_boundary_edges", r.nonmanifold_boundary_edges},
                         {"nonmanifold_vertices", r.nonmanifold_vertices},
                         {"dangling_vertices", r.dangling_vertices}};
  for (const auto& [name, count] : expected)
    EXPECT_TRUE(actual.count(name)) << "no count named " << name;
  for (const auto& [name, count] : actual) {
    const auto it = expected.find(name);
    EXPECT_EQ(count, it == expected.end() ? 0u : it->second) << name;
  }
  EXPECT_EQ(r.ok(), expected.empty()) << r.summary();
}

ValidityOptions orientation_unchecked() {
  ValidityOptions o;
  o.require_positive = false;
  return o;
}

ValidityOptions manifold_unchecked() {
  ValidityOptions o;
  o.check_manifold = false;
  return o;
}

ValidityOptions dangling_unchecked() {
  ValidityOptions o;
  o.check_dangling = false;
  return o;
}

// The right-corner tet (0, e1, e2, e3), positive.
Mesh single_tet() {
  return {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}, {{0, 1, 2, 3}}};
}

// The corner tet and a second one on its face (1, 2, 3) with apex 4 = (1,1,1)
// beyond it. The corner tet traverses the face as (1, 2, 3) (outward), so the
// second one must traverse it as (1, 3, 2): tet (4, 1, 3, 2).
Mesh two_tets() {
  Mesh m = single_tet();
  m.points.push_back(Vec3(1, 1, 1));
  m.tets.push_back({4, 1, 3, 2});
  return m;
}

// Cube [0,1]^3 split into 5 tets (four corners cut off and a central tet).
Mesh cube_five_tets() {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.points.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  m.tets = {{0, 1, 2, 4}, {3, 2, 1, 7}, {5, 4, 7, 1}, {6, 7, 4, 2}, {1, 2, 4, 7}};
  orient_positive(m);
  return m;
}

// n x n x n cubes, each split into the 6 tets around its main diagonal
// (Kuhn's subdivision, conforming across cubes).
Mesh structured_cube(int n) {
  Mesh m;
  auto id = [n](int i, int j, int k) { return static_cast<index_t>((k * (n + 1) + j) * (n + 1) + i); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.points.push_back(Vec3(i, j, k));
  const int order[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& axes : order) {
          int c[3] = {i, j, k};
          Tet t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[axes[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          m.tets.push_back(t);
        }
  orient_positive(m);
  return m;
}

// ------------------------------------------------------------ valid meshes

TEST(CheckValidity, SingleTet) {
  const ValidityReport r = check(single_tet());
  EXPECT_TRUE(r.ok()) << r.summary();
  expect_counts(r, Counts{});
  EXPECT_EQ(r.tets, 1u);
  EXPECT_EQ(r.points, 4u);
  EXPECT_EQ(r.boundary_faces, 4u);
  EXPECT_TRUE(r.first_bad_tets.empty());
  EXPECT_EQ(r.summary(), "valid: 1 tets, 4 points, 4 boundary faces");
}

TEST(CheckValidity, EmptyMesh) {
  const ValidityReport r = check_validity({}, {});
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.boundary_faces, 0u);
}

TEST(CheckValidity, TwoTetsSharingAFace) {
  const Mesh m = two_tets();
  ASSERT_GT(volume6(m, m.tets[1]), 0);
  const ValidityReport r = check(m);
  EXPECT_TRUE(r.ok()) << r.summary();
  EXPECT_EQ(r.boundary_faces, 6u);
}

TEST(CheckValidity, CubeFiveTets) {
  const ValidityReport r = check(cube_five_tets());
  EXPECT_TRUE(r.ok()) << r.summary();
  EXPECT_EQ(r.boundary_faces, 12u);
}

TEST(CheckValidity, StructuredCube) {
  for (int n : {1, 2, 3, 5, 8}) {
    const Mesh m = structured_cube(n);
    const ValidityReport r = check(m);
    EXPECT_TRUE(r.ok()) << "n = " << n << ": " << r.summary();
    EXPECT_EQ(r.tets, static_cast<std::size_t>(6 * n * n * n));
    EXPECT_EQ(r.boundary_faces, static_cast<std::size_t>(12 * n * n)) << "n = " << n;
  }
}

TEST(CheckValidity, TetOrderDoesNotMatter) {
  Mesh m = structured_cube(3);
  std::reverse(m.tets.begin(), m.tets.end());
  for (Tet& t : m.tets) std::rotate(t.begin(), t.begin() + 2, t.end());  // even permutation
  const ValidityReport r = check(m);
  EXPECT_TRUE(r.ok()) << r.summary();
  EXPECT_EQ(r.boundary_faces, 108u);
}

// -------------------------------------------------------- orientation

TEST(CheckValidity, OrientationMismatch) {
  // The second tet traverses the shared face in the same order as the first,
  // which also makes it geometrically inverted.
  Mesh m = two_tets();
  m.tets[1] = {4, 1, 2, 3};
  ValidityReport r = check(m);
  expect_counts(r, {{"inverted", 1}, {"orientation_mismatches", 1}});
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{0, 1}));

  // Without the geometric check only the combinatorial mismatch remains.
  r = check(m, orientation_unchecked());
  expect_counts(r, {{"orientation_mismatches", 1}});
  EXPECT_FALSE(r.ok());
}

TEST(CheckValidity, InvertedTet) {
  // Apex moved to the first tet's side of the shared face: orientation
  // consistent, volume negative (a fold).
  Mesh m = two_tets();
  m.points[4] = Vec3(0.1, 0.1, 0.1);
  const ValidityReport r = check(m);
  expect_counts(r, {{"inverted", 1}});
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{1}));
  EXPECT_NE(r.summary().find("1 inverted tet (negative volume)"), std::string::npos) << r.summary();
  EXPECT_TRUE(check(m, orientation_unchecked()).ok());
}

TEST(CheckValidity, FlatTet) {
  // Apex in the plane x + y + z = 1 of the shared face (exactly).
  Mesh m = two_tets();
  m.points[4] = Vec3(1, 1, -1);
  const ValidityReport r = check(m);
  expect_counts(r, {{"degenerate", 1}});
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{1}));
}

TEST(CheckValidity, AllNegativeMesh) {
  Mesh m = structured_cube(2);
  for (Tet& t : m.tets) std::swap(t[0], t[1]);
  expect_counts(check(m), {{"inverted", 48}});
  EXPECT_TRUE(check(m, orientation_unchecked()).ok());
}

// --------------------------------------------------------- conformity

TEST(CheckValidity, ThreeTetsOnOneFace) {
  Mesh m = two_tets();
  m.points.push_back(Vec3(2, 2, 2));
  m.tets.push_back({5, 1, 3, 2});
  ASSERT_GT(volume6(m, m.tets[2]), 0);
  const ValidityReport r = check(m);
  // The face's three edges each carry three boundary faces; its three
  // vertices see tets that no manifold face connects.
  expect_counts(r, {{"overshared_faces", 1}, {"nonmanifold_boundary_edges", 3},
                    {"nonmanifold_vertices", 3}});
  EXPECT_EQ(r.boundary_faces, 9u);
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{0, 1, 2}));
}

TEST(CheckValidity, DuplicateTet) {
  // Same orientation twice: all four faces interior and mismatched.
  Mesh m = single_tet();
  m.tets.push_back(m.tets[0]);
  ValidityReport r = check(m);
  expect_counts(r, {{"orientation_mismatches", 4}, {"duplicate_tets", 1}});
  EXPECT_EQ(r.boundary_faces, 0u);

  // Mirrored copy: orientation consistent, but the copy is inverted.
  m.tets[1] = {1, 0, 2, 3};
  r = check(m);
  expect_counts(r, {{"inverted", 1}, {"duplicate_tets", 1}});
}

TEST(CheckValidity, DuplicateTetInAMesh) {
  Mesh m = structured_cube(2);
  m.tets.push_back(m.tets[17]);
  const ValidityReport r = check(m);
  EXPECT_EQ(r.duplicate_tets, 1u);
  EXPECT_EQ(r.inverted + r.degenerate + r.index_out_of_range + r.dangling_vertices, 0u);
  EXPECT_FALSE(r.ok());
}

TEST(CheckValidity, TripleTet) {
  // Three copies: two duplicates; every face in three tets.
  Mesh m = single_tet();
  m.tets.push_back(m.tets[0]);
  m.tets.push_back(m.tets[0]);
  // No face is manifold, so no face connects the copies at any vertex.
  expect_counts(check(m), {{"overshared_faces", 4}, {"duplicate_tets", 2},
                           {"nonmanifold_vertices", 4}});
}

// ---------------------------------------------------------- manifoldness

TEST(CheckValidity, TwoTetsSharingOnlyAnEdge) {
  // Edge (0, 1) of the corner tet and of a tet below it.
  Mesh m = single_tet();
  m.points.push_back(Vec3(0, -1, 0));
  m.points.push_back(Vec3(0, 0, -1));
  m.tets.push_back({0, 1, 4, 5});
  ASSERT_GT(volume6(m, m.tets[1]), 0);
  const ValidityReport r = check(m);
  expect_counts(r, {{"nonmanifold_boundary_edges", 1}, {"nonmanifold_vertices", 2}});
  EXPECT_EQ(r.boundary_faces, 8u);
  EXPECT_EQ(r.first_bad_vertices, (std::vector<index_t>{0, 1}));
  EXPECT_TRUE(check(m, manifold_unchecked()).ok());
}

TEST(CheckValidity, TwoTetsSharingOnlyAVertex) {
  Mesh m = single_tet();
  m.points.push_back(Vec3(-1, 0, 0));
  m.points.push_back(Vec3(0, -1, 0));
  m.points.push_back(Vec3(0, 0, -1));
  m.tets.push_back({0, 4, 5, 6});
  orient_positive(m);
  const ValidityReport r = check(m);
  expect_counts(r, {{"nonmanifold_vertices", 1}});
  EXPECT_EQ(r.first_bad_vertices, (std::vector<index_t>{0}));
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{0, 1}));
}

TEST(CheckValidity, PinchedVertexTwoFans) {
  // Six tets from v = origin to a triangulated band around it (rings of three
  // points at z = +1 and z = -1): a prism with a conical dent in each cap,
  // both dents reaching v. The tets at v are face-connected, but its boundary
  // faces form two fans (the top and the bottom cone).
  Mesh m;
  m.points.push_back(Vec3(0, 0, 0));
  for (double z : {1.0, -1.0})
    for (int i = 0; i < 3; ++i) {
      const double angle = 2 * std::acos(-1.0) * i / 3;
      m.points.push_back(Vec3(std::cos(angle), std::sin(angle), z));
    }
  for (index_t i = 0; i < 3; ++i) {
    const index_t a0 = 1 + i, a1 = 1 + (i + 1) % 3, b0 = 4 + i, b1 = 4 + (i + 1) % 3;
    m.tets.push_back({0, a0, a1, b0});
    m.tets.push_back({0, a1, b1, b0});
  }
  orient_positive(m);
  const ValidityReport r = check(m);
  expect_counts(r, {{"nonmanifold_vertices", 1}});
  EXPECT_EQ(r.boundary_faces, 12u);
  EXPECT_EQ(r.first_bad_vertices, (std::vector<index_t>{0}));
}

TEST(CheckValidity, ConeOverTorus) {
  // Combinatorial only (no embedding with positive tets exists): v joined to
  // the 7-vertex torus. v's tets are face-connected and it has no boundary
  // face, yet its link is a torus (Euler characteristic 0, not 2).
  Mesh m;
  m.points.push_back(Vec3(0, 0, 0));
  for (int i = 0; i < 7; ++i) m.points.push_back(Vec3(std::cos(i), std::sin(i), 0.1 * i));
  for (index_t i = 0; i < 7; ++i) {
    m.tets.push_back({0, 1 + i, 1 + (i + 1) % 7, 1 + (i + 3) % 7});
    m.tets.push_back({0, 1 + i, 1 + (i + 3) % 7, 1 + (i + 2) % 7});
  }
  const ValidityReport r = check(m, orientation_unchecked());
  expect_counts(r, {{"nonmanifold_vertices", 1}});
  EXPECT_EQ(r.boundary_faces, 14u);
  EXPECT_EQ(r.first_bad_vertices, (std::vector<index_t>{0}));
}

// ------------------------------------------------------------ bad input

TEST(CheckValidity, DanglingVertex) {
  Mesh m = single_tet();
  m.points.push_back(Vec3(5, 5, 5));
  const ValidityReport r = check(m);
  expect_counts(r, {{"dangling_vertices", 1}});
  EXPECT_EQ(r.first_bad_vertices, (std::vector<index_t>{4}));
  EXPECT_TRUE(r.first_bad_tets.empty());
  EXPECT_TRUE(check(m, dangling_unchecked()).ok());
}

TEST(CheckValidity, IndexOutOfRange) {
  Mesh m = single_tet();
  m.tets.push_back({0, 1, 2, 4});
  m.tets.push_back({-1, 1, 2, 3});
  const ValidityReport r = check(m);
  expect_counts(r, {{"index_out_of_range", 2}});
  EXPECT_EQ(r.boundary_faces, 4u);  // the bad tets take no further part
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{1, 2}));
}

TEST(CheckValidity, IndexOutOfRangeLeavesPointUnused) {
  Mesh m = single_tet();
  m.tets[0][3] = 7;
  expect_counts(check(m), {{"index_out_of_range", 1}, {"dangling_vertices", 1}});
}

TEST(CheckValidity, RepeatedVertex) {
  Mesh m = single_tet();
  m.tets.push_back({0, 1, 1, 2});
  const ValidityReport r = check(m);
  expect_counts(r, {{"repeated_vertex", 1}});
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{1}));
}

TEST(CheckValidity, NonFinitePoint) {
  Mesh m = two_tets();
  m.points[4].y() = std::numeric_limits<double>::quiet_NaN();
  const ValidityReport r = check(m);
  expect_counts(r, {{"nonfinite_points", 1}});  // orientation not evaluated
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{1}));
  EXPECT_EQ(r.first_bad_vertices, (std::vector<index_t>{4}));

  m.points[2].x() = std::numeric_limits<double>::infinity();
  expect_counts(check(m), {{"nonfinite_points", 2}});
}

TEST(CheckValidity, FirstBadTetsAreCapped) {
  Mesh m = structured_cube(3);
  for (Tet& t : m.tets) std::swap(t[0], t[1]);
  const ValidityReport r = check(m);
  EXPECT_EQ(r.inverted, m.tets.size());
  EXPECT_EQ(r.first_bad_tets, (std::vector<index_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
}

TEST(CheckValidity, SummaryOneLinePerProblem) {
  Mesh m = two_tets();
  m.tets[1] = {4, 1, 2, 3};
  m.points.push_back(Vec3(9, 9, 9));
  const std::string s = check(m).summary();
  EXPECT_NE(s.find("1 inverted tet (negative volume)"), std::string::npos) << s;
  EXPECT_NE(s.find("1 interior face with the same orientation"), std::string::npos) << s;
  EXPECT_NE(s.find("1 dangling point"), std::string::npos) << s;
  EXPECT_NE(s.find("first bad tets: 0 1"), std::string::npos) << s;
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 4) << s;  // 3 problems, 2 id lists
}

}  // namespace
}  // namespace femorph
