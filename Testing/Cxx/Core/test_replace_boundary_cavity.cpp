// TetMesh::replace_boundary_cavity (Adapt's assembly mode, thesis 3.7.4): a
// cavity on the domain's boundary replaced by tets whose boundary differs
// there; the faces with the kept tets must stay. Hand-built meshes.
#include "mesh/tet_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace femorph {
namespace {

// Two parts that touch on the triangle (0, 1, 2) of z = 0 without sharing
// it: part A, the tet (0 1 2 3) above z = 0 (apex 3 at z = 1),
// part B the tet (4 6 5 7) below (4, 5, 6 at the positions of 0, 1, 2,
// apex 7 at z = -1), and a third tet (0 1 3 8) of part A beside the first.
struct TwoParts {
  std::vector<Vec3> points{{0, 0, 0},  {1, 0, 0},  {0, 1, 0}, {0, 0, 1}, {0, 0, 0},
                           {1, 0, 0},  {0, 1, 0},  {0, 0, -1}, {0.5, -1, 0.5}};
  std::vector<Tet> tets{{{0, 1, 2, 3}}, {{4, 6, 5, 7}}, {{0, 8, 1, 3}}};
};

std::size_t boundary_faces(const TetMesh& m) {
  std::size_t n = 0;
  for (index_t t = 0; t < m.tet_slots(); ++t)
    if (m.tet_alive(t))
      for (int f = 0; f < 4; ++f) n += m.is_boundary_face(t, f);
  return n;
}

TEST(ReplaceBoundaryCavity, TwoPartsBecomeConformal) {
  const TwoParts in;
  TetMesh m;
  ASSERT_TRUE(m.build(in.points, in.tets));
  ASSERT_EQ(boundary_faces(m), 10u);  // 4 + 4 + 4, the two tets of A sharing one
  // The cavity: A's first tet and B's tet; B's points 4, 5, 6 become 0, 1, 2.
  const std::vector<index_t> cavity{0, 1};
  const std::vector<Tet> now{{{0, 1, 2, 3}}, {{0, 2, 1, 7}}};
  const Status s = m.replace_boundary_cavity(cavity, now, {0, 1}, {}, {});
  ASSERT_TRUE(s) << s.message;
  EXPECT_TRUE(m.check_consistency()) << m.check_consistency().message;
  // The face (0, 1, 2) is shared: 2 + 3 + 3 boundary faces, the kept face
  // between A's tets still linked.
  EXPECT_EQ(boundary_faces(m), 8u);
  EXPECT_EQ(m.live_tets(), 3u);
  int lf = 0;
  const index_t t = m.find_face(0, 1, 2, &lf);
  ASSERT_GE(t, 0);
  EXPECT_GE(m.adjacency(t, lf), 0);
  const index_t u = m.find_face(0, 1, 3, &lf);
  ASSERT_GE(u, 0);
  EXPECT_GE(m.adjacency(u, lf), 0);
  // B's own copies of the face's points are gone; 0 stays on the boundary.
  EXPECT_FALSE(m.vertex_alive(4));
  EXPECT_FALSE(m.vertex_alive(5));
  EXPECT_FALSE(m.vertex_alive(6));
  EXPECT_TRUE(m.on_boundary(0));
}

TEST(ReplaceBoundaryCavity, AFaceWithAKeptTetMustStay) {
  const TwoParts in;
  TetMesh m;
  ASSERT_TRUE(m.build(in.points, in.tets));
  const std::vector<Vec3> before(m.points().begin(), m.points().end());
  // A's first tet shares (0, 1, 3) with the kept tet (0 8 1 3): a refill
  // without that face is refused, and nothing changes.
  const std::vector<index_t> cavity{0, 1};
  const std::vector<Tet> now{{{0, 2, 1, 7}}};
  const Status s = m.replace_boundary_cavity(cavity, now, {0}, {}, {});
  EXPECT_FALSE(s);
  EXPECT_NE(s.message.find("kept tets"), std::string::npos) << s.message;
  EXPECT_EQ(m.live_tets(), 3u);
  EXPECT_EQ(boundary_faces(m), 10u);
  EXPECT_TRUE(m.check_consistency());
  EXPECT_TRUE(std::equal(before.begin(), before.end(), m.points().begin()));
}

}  // namespace
}  // namespace femorph
