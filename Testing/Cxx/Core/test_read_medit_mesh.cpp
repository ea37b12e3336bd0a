// Medit .mesh reader: the real parts (fandisk, chamfer), a small file with
// every kind of section we skip, and the error messages for broken files.
#include "io/read_medit_mesh.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace femorph {
namespace {

namespace fs = std::filesystem;

const std::string kRealParts = FEMORPH_REALPARTS_DIR;

/// Writes `text` to a file in a per-test temporary folder and returns its path.
std::string write_temp(const std::string& name, const std::string& text) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(::testing::TempDir()) /
                       (std::string("femorph_medit_") + info->name());
  fs::create_directories(dir);
  const fs::path file = dir / name;
  std::ofstream(file, std::ios::binary) << text;
  return file.string();
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

template <std::size_t N>
void expect_indices_in_range(const std::vector<std::array<index_t, N>>& elements,
                             std::size_t n_points) {
  std::size_t bad = 0;
  for (const auto& e : elements)
    for (index_t v : e)
      if (v < 0 || static_cast<std::size_t>(v) >= n_points) ++bad;
  EXPECT_EQ(bad, 0u);
}

void expect_finite(const MeditMesh& m) {
  std::size_t bad = 0;
  for (const Vec3& p : m.points)
    if (!p.allFinite()) ++bad;
  EXPECT_EQ(bad, 0u);
}

double signed_volume6(const MeditMesh& m, const Tet& t) {
  const Vec3& a = m.points[t[0]];
  return (m.points[t[1]] - a).dot((m.points[t[2]] - a).cross(m.points[t[3]] - a));
}

// ---------------------------------------------------------------------------
// Real parts

TEST(ReadMeditMesh, Fandisk) {
  const std::string path = kRealParts + "/fandisk_tet.mesh";
  if (!fs::exists(path)) GTEST_SKIP() << "real parts not found: " << path;
  MeditMesh m;
  const auto start = std::chrono::steady_clock::now();
  const Status s = read_medit_mesh(path, m);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "fandisk: " << m.points.size() << " points, " << m.tets.size() << " tets, "
            << m.triangles.size() << " triangles read in " << seconds << " s\n";
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(m.tets.size(), 56080u);
  EXPECT_EQ(m.points.size(), 12336u);
  EXPECT_EQ(m.triangles.size(), 13496u);
  EXPECT_EQ(m.point_refs.size(), m.points.size());
  EXPECT_EQ(m.tet_refs.size(), m.tets.size());
  EXPECT_EQ(m.triangle_refs.size(), m.triangles.size());
  expect_indices_in_range(m.tets, m.points.size());
  expect_indices_in_range(m.triangles, m.points.size());
  expect_finite(m);

  Vec3 lo = m.points.front(), hi = m.points.front();
  for (const Vec3& p : m.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 extent = hi - lo;
  EXPECT_NEAR(extent.x(), 0.634, 0.005);
  EXPECT_NEAR(extent.y(), 0.689, 0.005);
  EXPECT_NEAR(extent.z(), 0.352, 0.005);

  // The first tet of the file: its 1-based indices shifted to 0-based, in the
  // file's order (no reorientation).
  std::ifstream in(path);
  std::string word;
  while (in >> word && word != "Tetrahedra") {
  }
  long long count = 0, v[4] = {0, 0, 0, 0};
  in >> count >> v[0] >> v[1] >> v[2] >> v[3];
  ASSERT_EQ(count, 56080);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(m.tets[0][k], v[k] - 1);
}

TEST(ReadMeditMesh, ChamferWithInteriorTriangles) {
  const std::string path = kRealParts + "/chamfer_tet.mesh";
  if (!fs::exists(path)) GTEST_SKIP() << "real parts not found: " << path;
  MeditMesh m;
  const Status s = read_medit_mesh(path, m);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(m.tets.size(), 11849u);
  EXPECT_EQ(m.points.size(), 2654u);
  // Boundary and interior triangles alike; Corners and Edges skipped.
  EXPECT_EQ(m.triangles.size(), 25169u);
  expect_indices_in_range(m.tets, m.points.size());
  expect_indices_in_range(m.triangles, m.points.size());
  expect_finite(m);
  std::size_t degenerate = 0;
  for (const Tet& t : m.tets)
    if (signed_volume6(m, t) == 0.0) ++degenerate;
  EXPECT_EQ(degenerate, 0u);
}

// ---------------------------------------------------------------------------
// A small file exercising the syntax

TEST(ReadMeditMesh, SmallFileWithSkippedSections) {
  // Version 2, keyword and value on one line, comments, CRLF line ends,
  // sections we skip before and between the ones we read, a negatively
  // oriented tet that must stay as written.
  const std::string text =
      "MeshVersionFormatted 2\r\n"
      "# a comment line\r\n"
      "Dimension 3\r\n"
      "Vertices\r\n"
      "5\r\n"
      "0 0 0 1\r\n"
      "1.0 0 0 2   # trailing comment\r\n"
      "0 1.5e0 0 3\r\n"
      "0 0 +2 4\r\n"
      "-1E-1 .25 3.0 5\r\n"
      "Corners\r\n3\r\n1\r\n2\r\n3\r\n"
      "Edges\r\n2\r\n1 2 7\r\n2 3 7\r\n"
      "Normals 1 0 0 1.0\r\n"
      "NormalAtVertices 1 1 1\r\n"
      "Tetrahedra\r\n"
      "2\r\n"
      "1 2 3 4 10\r\n"
      "1 3 2 5 -11\r\n"
      "RequiredVertices 1 4\r\n"
      "triangles\r\n"  // keywords are case-insensitive
      "1\r\n"
      "2 3 4 20\r\n"
      "Ridges 1 1\r\n"
      "End\r\n"
      "this text after End is ignored\r\n";
  MeditMesh m;
  const Status s = read_medit_mesh(write_temp("small.mesh", text), m);
  ASSERT_TRUE(s.ok) << s.message;
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.points[1], Vec3(1.0, 0.0, 0.0));
  EXPECT_EQ(m.points[2], Vec3(0.0, 1.5, 0.0));
  EXPECT_EQ(m.points[3], Vec3(0.0, 0.0, 2.0));
  EXPECT_EQ(m.points[4], Vec3(-0.1, 0.25, 3.0));
  EXPECT_EQ(m.point_refs, (std::vector<index_t>{1, 2, 3, 4, 5}));
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(m.tets[0], (Tet{0, 1, 2, 3}));
  EXPECT_EQ(m.tets[1], (Tet{0, 2, 1, 4}));
  EXPECT_EQ(m.tet_refs, (std::vector<index_t>{10, -11}));
  EXPECT_GT(signed_volume6(m, m.tets[0]), 0.0);
  EXPECT_LT(signed_volume6(m, m.tets[1]), 0.0);  // kept as in the file
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], (std::array<index_t, 3>{1, 2, 3}));
  EXPECT_EQ(m.triangle_refs, (std::vector<index_t>{20}));
}

TEST(ReadMeditMesh, ElementsBeforeVerticesAreChecked) {
  MeditMesh m;
  Status s = read_medit_mesh(
      write_temp("order.mesh",
                 "MeshVersionFormatted 1\nDimension\n3\nTetrahedra\n1\n1 2 3 4 0\n"
                 "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"),
      m);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(m.tets.size(), 1u);

  s = read_medit_mesh(
      write_temp("order_bad.mesh",
                 "MeshVersionFormatted 1\nDimension\n3\nTetrahedra\n1\n1 2 3 9 0\n"
                 "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"),
      m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, "Tetrahedra")) << s.message;
  EXPECT_TRUE(contains(s.message, "vertex index 9 out of range 1..4")) << s.message;
  EXPECT_TRUE(m.tets.empty());
}

// ---------------------------------------------------------------------------
// Error messages

TEST(ReadMeditMesh, MissingFile) {
  MeditMesh m;
  const std::string path = ::testing::TempDir() + "/femorph_no_such_file.mesh";
  const Status s = read_medit_mesh(path, m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, path)) << s.message;
  EXPECT_TRUE(contains(s.message, "cannot open")) << s.message;
  EXPECT_TRUE(contains(s.message, "no such file")) << s.message;
}

TEST(ReadMeditMesh, TruncatedVerticesAtEndOfFile) {
  MeditMesh m;
  const std::string path = write_temp(
      "truncated.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1");
  const Status s = read_medit_mesh(path, m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, path)) << s.message;
  EXPECT_TRUE(contains(s.message, "section Vertices")) << s.message;
  EXPECT_TRUE(contains(s.message, "end of file")) << s.message;
  EXPECT_TRUE(contains(s.message, "entry 3 of 4")) << s.message;
  EXPECT_TRUE(contains(s.message, "truncated")) << s.message;
  EXPECT_TRUE(m.points.empty());
}

TEST(ReadMeditMesh, TruncatedVerticesBeforeNextSection) {
  MeditMesh m;
  const std::string path =
      write_temp("short.mesh",
                 "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n"
                 "Tetrahedra\n1\n1 2 3 4 0\nEnd\n");
  const Status s = read_medit_mesh(path, m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, path + ":7:")) << s.message;  // line of "Tetrahedra"
  EXPECT_TRUE(contains(s.message, "section Vertices")) << s.message;
  EXPECT_TRUE(contains(s.message, "truncated")) << s.message;
  EXPECT_TRUE(contains(s.message, "'Tetrahedra'")) << s.message;
}

TEST(ReadMeditMesh, IndexOutOfRange) {
  MeditMesh m;
  const std::string path =
      write_temp("range.mesh",
                 "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n"
                 "0 1 0 0\n0 0 1 0\nTetrahedra\n2\n1 2 3 4 0\n1 2 5 4 0\nEnd\n");
  const Status s = read_medit_mesh(path, m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, path + ":12:")) << s.message;
  EXPECT_TRUE(contains(s.message, "section Tetrahedra")) << s.message;
  EXPECT_TRUE(contains(s.message, "entry 2")) << s.message;
  EXPECT_TRUE(contains(s.message, "vertex index 5 out of range 1..4")) << s.message;

  // 0 is out of range too: Medit counts from 1.
  const Status z = read_medit_mesh(
      write_temp("zero.mesh",
                 "MeshVersionFormatted 1\nDimension 3\nVertices\n3\n0 0 0 0\n1 0 0 0\n"
                 "0 1 0 0\nTriangles\n1\n0 1 2 0\n"),
      m);
  ASSERT_FALSE(z.ok);
  EXPECT_TRUE(contains(z.message, "section Triangles")) << z.message;
  EXPECT_TRUE(contains(z.message, "vertex index 0 out of range 1..3")) << z.message;
}

TEST(ReadMeditMesh, Dimension2) {
  MeditMesh m;
  const std::string path = write_temp(
      "flat.mesh", "MeshVersionFormatted 1\nDimension\n2\nVertices\n1\n0 0 0\nEnd\n");
  const Status s = read_medit_mesh(path, m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, path + ":3:")) << s.message;
  EXPECT_TRUE(contains(s.message, "Dimension 2 is not supported")) << s.message;
}

TEST(ReadMeditMesh, NonNumericToken) {
  MeditMesh m;
  const std::string path =
      write_temp("word.mesh",
                 "MeshVersionFormatted 1\nDimension 3\nVertices\n2\n0 0 0 0\n1 zero 0 0\n");
  const Status s = read_medit_mesh(path, m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, path + ":6:")) << s.message;
  EXPECT_TRUE(contains(s.message, "non-numeric token 'zero'")) << s.message;
  EXPECT_TRUE(contains(s.message, "entry 2 of 2")) << s.message;

  const Status r = read_medit_mesh(
      write_temp("realindex.mesh",
                 "MeshVersionFormatted 1\nDimension 3\nVertices\n3\n0 0 0 0\n1 0 0 0\n"
                 "0 1 0 0\nTriangles\n1\n1 2.5 3 0\n"),
      m);
  ASSERT_FALSE(r.ok);
  EXPECT_TRUE(contains(r.message, "vertex index")) << r.message;
  EXPECT_TRUE(contains(r.message, "'2.5'")) << r.message;
}

TEST(ReadMeditMesh, NotAMeditFile) {
  MeditMesh m;
  const Status s = read_medit_mesh(
      write_temp("other.vtk", "# vtk DataFile Version 3.0\nsomething else\n"), m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, "not an ASCII Medit file")) << s.message;

  const Status e = read_medit_mesh(write_temp("empty.mesh", ""), m);
  ASSERT_FALSE(e.ok);
  EXPECT_TRUE(contains(e.message, "not an ASCII Medit file")) << e.message;

  const Status v = read_medit_mesh(write_temp("novertices.mesh", "MeshVersionFormatted 1\n"
                                                                  "Dimension 3\nEnd\n"),
                                   m);
  ASSERT_FALSE(v.ok);
  EXPECT_TRUE(contains(v.message, "no Vertices section")) << v.message;
}

TEST(ReadMeditMesh, AbsurdCountFailsWithoutHugeAllocation) {
  MeditMesh m;
  const Status s = read_medit_mesh(
      write_temp("huge.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n2000000000\n"
                              "0 0 0 0\n"),
      m);
  ASSERT_FALSE(s.ok);
  EXPECT_TRUE(contains(s.message, "truncated")) << s.message;
  EXPECT_TRUE(contains(s.message, "entry 2 of 2000000000")) << s.message;

  const Status n = read_medit_mesh(
      write_temp("negative.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n-3\n"), m);
  ASSERT_FALSE(n.ok);
  EXPECT_TRUE(contains(n.message, "negative number of entries")) << n.message;
}

}  // namespace
}  // namespace femorph
