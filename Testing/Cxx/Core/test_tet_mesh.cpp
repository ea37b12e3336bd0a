// TetMesh construction and local operations on hand-built meshes with the
// exact expected connectivity, including refusals.
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "test_meshes.h"
#include "test_threads.h"

#include <gtest/gtest.h>

#include <limits>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <type_traits>
#include <utility>

namespace femorph {
namespace {

using Sets = std::vector<std::array<index_t, 4>>;

/// Live tets as sorted vertex sets, sorted: connectivity independent of slots
/// and of the order inside each tet.
Sets tet_sets(const TetMesh& m) {
  Sets out;
  for (index_t t = 0; t < m.tet_slots(); ++t) {
    if (!m.tet_alive(t)) continue;
    Tet s = m.tet(t);
    std::sort(s.begin(), s.end());
    out.push_back(s);
  }
  std::sort(out.begin(), out.end());
  return out;
}

Sets sorted_sets(Sets s) {
  for (auto& t : s) std::sort(t.begin(), t.end());
  std::sort(s.begin(), s.end());
  return s;
}

double volume(const TetMesh& m) {
  const CompactMesh c = m.compact();
  return testing::total_volume(c.points, c.tets);
}

std::size_t boundary_faces(const TetMesh& m) {
  std::size_t n = 0;
  for (index_t t = 0; t < m.tet_slots(); ++t)
    if (m.tet_alive(t))
      for (int f = 0; f < 4; ++f) n += m.is_boundary_face(t, f);
  return n;
}

/// Everything a refused operation must leave unchanged.
struct Snapshot {
  std::vector<Tet> tets, adjacency;
  std::vector<Vec3> points;
  explicit Snapshot(const TetMesh& m) {
    for (index_t t = 0; t < m.tet_slots(); ++t) {
      tets.push_back(m.tet(t));
      adjacency.push_back({m.adjacency(t, 0), m.adjacency(t, 1), m.adjacency(t, 2), m.adjacency(t, 3)});
    }
    points = m.points();
  }
  bool operator==(const Snapshot& o) const { return tets == o.tets && adjacency == o.adjacency && points == o.points; }
};

void expect_valid(const TetMesh& m) {
  const Status s = m.check_consistency();
  EXPECT_TRUE(s.ok) << s.message;
  const CompactMesh c = m.compact();
  const ValidityReport r = check_validity(c.points, c.tets);
  EXPECT_TRUE(r.ok()) << r.summary();
}

// Two tets on the triangle (0, 1, 2) in the plane z = 0, apexes 3 above and
// 4 below.
TetMesh two_tets(double apex_x = 0.3) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {apex_x, 0.3, 1}, {apex_x, 0.3, -1}};
  std::vector<Tet> t = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  TetMesh m;
  const Status s = m.build(p, t);
  EXPECT_TRUE(s.ok) << s.message;
  return m;
}

// An octahedron: ring c0..c3 in the plane z = 0, a above and b below; four
// tets around the edge (a, b).
TetMesh octahedron(bool convex = true) {
  std::vector<Vec3> p = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  if (!convex) {
    // Star-shaped around the edge but reflex at c1: the diagonal (c0, c2) runs
    // outside the ring, (c1, c3) inside.
    p[2] = Vec3(1, 0.6, 0);
    p[3] = Vec3(0, 0.3, 0);
    p[4] = Vec3(-1, 0.6, 0);
  }
  // a = 0, b = 1, c0..c3 = 2..5
  std::vector<Tet> t;
  for (int i = 0; i < 4; ++i) {
    Tet T = {0, 1, static_cast<index_t>(2 + i), static_cast<index_t>(2 + (i + 1) % 4)};
    const Vec3& p0 = p[T[0]];
    if ((p[T[1]] - p0).dot((p[T[2]] - p0).cross(p[T[3]] - p0)) < 0) std::swap(T[2], T[3]);
    t.push_back(T);
  }
  TetMesh m;
  const Status s = m.build(p, t);
  EXPECT_TRUE(s.ok) << s.message;
  return m;
}

// ---------------------------------------------------------------------------
TEST(TetMeshBuild, AdjacencyBoundaryAndClasses) {
  TetMesh m = two_tets();
  EXPECT_EQ(m.live_tets(), 2u);
  EXPECT_EQ(boundary_faces(m), 6u);
  // Face 3 of tet 0 is (0, 1, 2), shared with tet 1's face opposite vertex 4.
  EXPECT_EQ(m.adjacency(0, 3), 4 * 1 + 3);
  EXPECT_EQ(m.adjacency(1, 3), 4 * 0 + 3);
  for (index_t v = 0; v < 5; ++v) EXPECT_EQ(m.vertex_class(v), VertexClass::Surface);
  expect_valid(m);
}

TEST(TetMeshBuild, FlipsAllNegativeInput) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 1}, {0.3, 0.3, -1}};
  std::vector<Tet> t = {{0, 2, 1, 3}, {0, 1, 2, 4}};  // both negative
  TetMesh m;
  BuildReport rep;
  ASSERT_TRUE(m.build(p, t, {}, &rep).ok);
  EXPECT_EQ(rep.flipped_tets, 2u);
  EXPECT_GT(m.orientation(0), 0);
  EXPECT_GT(m.orientation(1), 0);
}

TEST(TetMeshBuild, MixedOrientationIsAnErrorWithTheCount) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 1}, {0.3, 0.3, -1}};
  std::vector<Tet> t = {{0, 1, 2, 3}, {0, 1, 2, 4}};  // second listed in the other convention
  TetMesh m;
  const Status s = m.build(p, t);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.message.find("mixed orientation"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("1 tet is"), std::string::npos) << s.message;
  EXPECT_EQ(m.live_tets(), 0u);
}

TEST(TetMeshBuild, InvertedTetNeedsPermission) {
  // Consistent connectivity, but apex 4 moved above the shared face: tet 1 is
  // geometrically inverted (as after a deformation).
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 1}, {0.3, 0.3, 0.5}};
  std::vector<Tet> t = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  TetMesh m;
  Status s = m.build(p, t);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.message.find("1 tet is inverted"), std::string::npos) << s.message;
  BuildOptions allow;
  allow.allow_inverted = true;
  BuildReport rep;
  s = m.build(p, t, allow, &rep);
  EXPECT_TRUE(s.ok) << s.message;
  EXPECT_EQ(rep.inverted_tets, 1u);
}

TEST(TetMeshBuild, BadInputMessages) {
  TetMesh m;
  EXPECT_NE(m.build({}, {}).message.find("no tetrahedra"), std::string::npos);
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_NE(m.build(p, {{0, 1, 2, 7}}).message.find("out of range"), std::string::npos);
  EXPECT_NE(m.build(p, {{0, 1, 1, 3}}).message.find("twice"), std::string::npos);
  auto q = p;
  q[2].x() = std::nan("");
  EXPECT_NE(m.build(q, {{0, 1, 2, 3}}).message.find("NaN"), std::string::npos);
  auto flat = p;
  flat[3] = Vec3(0.2, 0.2, 0);
  EXPECT_NE(m.build(flat, {{0, 1, 2, 3}}).message.find("zero volume"), std::string::npos);
  // Two tets touching at one vertex only.
  std::vector<Vec3> bow = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  const Status s = m.build(bow, {{0, 1, 2, 3}, {0, 5, 4, 6}});
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.message.find("not manifold"), std::string::npos) << s.message;
  // Three tets on one face.
  std::vector<Vec3> fan = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 1}, {0.3, 0.3, -1}, {0.3, 0.3, 2}};
  const Status s3 = m.build(fan, {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}});
  EXPECT_FALSE(s3.ok);
  EXPECT_NE(s3.message.find("more than two tets"), std::string::npos) << s3.message;
  // Region ids: -1 or labels up to INT_MAX / 2; INT_MAX would overflow the
  // boundary code -2 - region.
  for (const index_t bad : {index_t(-2), std::numeric_limits<index_t>::max() / 2 + 1,
                            std::numeric_limits<index_t>::max(), std::numeric_limits<index_t>::min()}) {
    BuildOptions options;
    options.face_regions = {{0, 1, bad, -1}};
    const Status r = m.build(p, {{0, 1, 2, 3}}, options);
    EXPECT_FALSE(r.ok) << bad;
    EXPECT_NE(r.message.find("face_regions names region " + std::to_string(bad) + " at tet 0, face 2"),
              std::string::npos)
        << r.message;
    EXPECT_EQ(m.live_tets(), 0u);
  }
  BuildOptions ok;
  ok.face_regions = {{0, 1, std::numeric_limits<index_t>::max() / 2, -1}};
  EXPECT_TRUE(m.build(p, {{0, 1, 2, 3}}, ok).ok);
}

TEST(TetMeshBuild, UnusedPointsAreDroppedAndReported) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {9, 9, 9}, {0, 1, 0}, {0, 0, 1}};
  TetMesh m;
  BuildReport rep;
  ASSERT_TRUE(m.build(p, {{0, 1, 3, 4}}, {}, &rep).ok);
  EXPECT_EQ(rep.unused_points, 1u);
  EXPECT_FALSE(m.vertex_alive(2));
  const CompactMesh c = m.compact();
  EXPECT_EQ(c.points.size(), 4u);
  EXPECT_EQ(c.vertex_map[2], kInvalidIndex);
  EXPECT_EQ(c.vertex_origin[2].ids[0], 3);  // output vertex 2 is input point 3
}

// ---------------------------------------------------------------------------
TEST(Flip23, ExactConnectivityAndBack) {
  TetMesh m = two_tets();
  const double v0 = volume(m);
  ASSERT_EQ(m.flip_23(0, 3), OpStatus::Ok);
  EXPECT_EQ(tet_sets(m), sorted_sets({{3, 4, 0, 1}, {3, 4, 1, 2}, {3, 4, 2, 0}}));
  EXPECT_EQ(m.touched_tets().size(), 3u);
  EXPECT_NEAR(volume(m), v0, 1e-15);
  EXPECT_EQ(boundary_faces(m), 6u);
  expect_valid(m);
  ASSERT_EQ(m.flip_32(3, 4), OpStatus::Ok);
  EXPECT_EQ(tet_sets(m), sorted_sets({{0, 1, 2, 3}, {0, 1, 2, 4}}));
  EXPECT_NEAR(volume(m), v0, 1e-15);
  expect_valid(m);
}

TEST(Flip23, RefusesWhenTheNewEdgeMissesTheFace) {
  TetMesh m = two_tets(1.5);  // apexes beyond edge (1, 2): segment misses the face
  const Snapshot before(m);
  EXPECT_EQ(m.flip_23(0, 3), OpStatus::Inverted);
  EXPECT_TRUE(Snapshot(m) == before);
  EXPECT_EQ(m.flip_23(0, 0), OpStatus::BoundaryEntity);
  EXPECT_TRUE(Snapshot(m) == before);
}

TEST(Flip32, RefusesWrongValenceAndBoundary) {
  TetMesh m = octahedron();
  const Snapshot before(m);
  EXPECT_EQ(m.flip_32(0, 1), OpStatus::WrongValence);
  EXPECT_EQ(m.flip_32(0, 2), OpStatus::BoundaryEntity);
  EXPECT_EQ(m.flip_32(2, 4), OpStatus::InvalidArgument);  // not an edge
  EXPECT_TRUE(Snapshot(m) == before);
}

TEST(Flip44, BothDiagonals) {
  for (int diagonal = 0; diagonal < 2; ++diagonal) {
    TetMesh m = octahedron();
    const double v0 = volume(m);
    ASSERT_EQ(m.flip_44(0, 1, diagonal), OpStatus::Ok);
    // The ring order starts anywhere; check the new edge is one diagonal and
    // the four tets are the octahedron around it.
    const bool d24 = m.has_edge(2, 4), d35 = m.has_edge(3, 5);
    EXPECT_NE(d24, d35);
    EXPECT_FALSE(m.has_edge(0, 1));
    if (d24) {
      EXPECT_EQ(tet_sets(m), sorted_sets({{2, 4, 3, 0}, {2, 4, 3, 1}, {2, 4, 5, 0}, {2, 4, 5, 1}}));
    } else {
      EXPECT_EQ(tet_sets(m), sorted_sets({{3, 5, 2, 0}, {3, 5, 2, 1}, {3, 5, 4, 0}, {3, 5, 4, 1}}));
    }
    EXPECT_NEAR(volume(m), v0, 1e-15);
    EXPECT_EQ(boundary_faces(m), 8u);
    expect_valid(m);
  }
}

TEST(Flip44, RefusesTheDiagonalOutsideANonConvexRing) {
  // The ring quad is not convex at c1, so the diagonal (c0, c2) = (2, 4)
  // leaves the octahedron; (c1, c3) = (3, 5) is fine.
  int refused = 0, accepted = 0;
  for (int diagonal = 0; diagonal < 2; ++diagonal) {
    TetMesh m = octahedron(false);
    const Snapshot before(m);
    const OpStatus s = m.flip_44(0, 1, diagonal);
    if (s == OpStatus::Ok) {
      ++accepted;
      EXPECT_TRUE(m.has_edge(3, 5));
      expect_valid(m);
    } else {
      ++refused;
      EXPECT_EQ(s, OpStatus::Inverted);
      EXPECT_TRUE(Snapshot(m) == before);
    }
  }
  EXPECT_EQ(refused, 1);
  EXPECT_EQ(accepted, 1);
}

// ---------------------------------------------------------------------------
TEST(SplitEdge, SingleTetMidpoint) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  BuildOptions opt;
  opt.face_regions = {{10, 11, 12, 13}};
  TetMesh m;
  ASSERT_TRUE(m.build(p, {{0, 1, 2, 3}}, opt).ok);
  index_t v = -1;
  ASSERT_EQ(m.split_edge(0, 1, nullptr, &v), OpStatus::Ok);
  EXPECT_EQ(v, 4);
  EXPECT_EQ(tet_sets(m), sorted_sets({{4, 1, 2, 3}, {0, 4, 2, 3}}));
  EXPECT_TRUE(m.point(v).isApprox(Vec3(0.5, 0, 0)));
  EXPECT_EQ(m.vertex_class(v), VertexClass::Curve);  // edge between faces 12 and 13
  EXPECT_EQ(m.vertex_origin(v).ids[0] + m.vertex_origin(v).ids[1], 1);
  EXPECT_DOUBLE_EQ(m.vertex_origin(v).weights[0], 0.5);
  EXPECT_EQ(boundary_faces(m), 6u);
  // Regions follow the faces: faces opposite vertex 0 / 1 keep 10 / 11, and
  // the split faces (containing the edge) keep 12 and 13.
  std::multiset<index_t> regions;
  for (index_t t = 0; t < m.tet_slots(); ++t) {
    if (!m.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f)
      if (m.is_boundary_face(t, f)) regions.insert(m.face_region(t, f));
  }
  EXPECT_EQ(regions, (std::multiset<index_t>{10, 11, 12, 12, 13, 13}));
  for (index_t t = 0; t < m.tet_slots(); ++t) {
    if (m.tet_alive(t)) {
      EXPECT_EQ(m.tet_origin(t), 0);
    }
  }
  expect_valid(m);
}

TEST(SplitEdge, RefusesAPositionThatInverts) {
  TetMesh m = two_tets();
  const Snapshot before(m);
  const Vec3 far(0.5, 0.0, 3.0);  // beyond apex 3
  EXPECT_EQ(m.split_edge(0, 1, &far, nullptr), OpStatus::Inverted);
  EXPECT_TRUE(Snapshot(m) == before);
  EXPECT_EQ(m.split_edge(3, 4, nullptr, nullptr), OpStatus::InvalidArgument);  // not an edge
}

TEST(SplitFace, InteriorFaceGivesSixTets) {
  TetMesh m = two_tets();
  const double v0 = volume(m);
  index_t v = -1;
  ASSERT_EQ(m.split_face(0, 3, nullptr, &v), OpStatus::Ok);
  EXPECT_EQ(v, 5);
  EXPECT_EQ(m.vertex_class(v), VertexClass::Inner);
  EXPECT_EQ(tet_sets(m), sorted_sets({{5, 1, 2, 3}, {0, 5, 2, 3}, {0, 1, 5, 3},
                                      {5, 2, 1, 4}, {0, 5, 1, 4}, {0, 2, 5, 4}}));
  EXPECT_NEAR(volume(m), v0, 1e-15);
  EXPECT_EQ(boundary_faces(m), 6u);
  expect_valid(m);
}

TEST(SplitFace, BoundaryFaceGivesThreeTets) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  TetMesh m;
  ASSERT_TRUE(m.build(p, {{0, 1, 2, 3}}).ok);
  index_t v = -1;
  ASSERT_EQ(m.split_face(0, 0, nullptr, &v), OpStatus::Ok);  // face (1, 2, 3)
  EXPECT_EQ(tet_sets(m), sorted_sets({{0, 4, 2, 3}, {0, 1, 4, 3}, {0, 1, 2, 4}}));
  EXPECT_EQ(m.vertex_class(v), VertexClass::Surface);
  EXPECT_EQ(boundary_faces(m), 6u);
  expect_valid(m);
}

// ---------------------------------------------------------------------------
// A collapse names its vertices' roles: Keep{} and Remove{} in that order;
// plain ids or swapped roles do not compile.
template <class K, class R, class = void>
struct CanCollapse : std::false_type {};
template <class K, class R>
struct CanCollapse<K, R, std::void_t<decltype(std::declval<TetMesh&>().collapse_edge(std::declval<K>(),
                                                                                      std::declval<R>(), nullptr))>>
    : std::true_type {};
template <class K, class R, class = void>
struct CanHalfEdgeCollapse : std::false_type {};
template <class K, class R>
struct CanHalfEdgeCollapse<
    K, R, std::void_t<decltype(std::declval<TetMesh&>().half_edge_collapse(std::declval<K>(), std::declval<R>()))>>
    : std::true_type {};

TEST(CollapseEdge, RolesAreTyped) {
  static_assert(CanCollapse<Keep, Remove>::value);
  static_assert(!CanCollapse<Remove, Keep>::value);
  static_assert(!CanCollapse<index_t, index_t>::value);
  static_assert(CanHalfEdgeCollapse<Keep, Remove>::value);
  static_assert(!CanHalfEdgeCollapse<Remove, Keep>::value);
  static_assert(!CanHalfEdgeCollapse<index_t, index_t>::value);
  static_assert(!std::is_convertible_v<index_t, Keep> && !std::is_convertible_v<Remove, Keep>);
  static_assert(!std::is_convertible_v<index_t, Remove> && !std::is_convertible_v<Keep, Remove>);
  // The vertex named Keep stays where it is, the one named Remove goes.
  TetMesh m = two_tets();
  index_t v = -1;
  ASSERT_EQ(m.split_edge(3, 0, nullptr, &v), OpStatus::Ok);
  TetMesh other = m;
  const Vec3 at3 = m.point(3), atv = m.point(v);
  ASSERT_EQ(m.half_edge_collapse(Keep{3}, Remove{v}), OpStatus::Ok);
  EXPECT_TRUE(m.vertex_alive(3));
  EXPECT_FALSE(m.vertex_alive(v));
  EXPECT_EQ(m.point(3), at3);
  ASSERT_EQ(other.half_edge_collapse(Keep{v}, Remove{3}), OpStatus::Ok);
  EXPECT_TRUE(other.vertex_alive(v));
  EXPECT_FALSE(other.vertex_alive(3));
  EXPECT_EQ(other.point(v), atv);
  expect_valid(m);
  expect_valid(other);
}

TEST(CollapseEdge, UndoesASplit) {
  TetMesh m = two_tets();
  index_t v = -1;
  ASSERT_EQ(m.split_edge(3, 0, nullptr, &v), OpStatus::Ok);
  ASSERT_EQ(m.half_edge_collapse(Keep{3}, Remove{v}), OpStatus::Ok);
  EXPECT_EQ(tet_sets(m), sorted_sets({{0, 1, 2, 3}, {0, 1, 2, 4}}));
  EXPECT_FALSE(m.vertex_alive(v));
  expect_valid(m);
}

TEST(CollapseEdge, LinkConditionRefusesASingleTet) {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  TetMesh m;
  ASSERT_TRUE(m.build(p, {{0, 1, 2, 3}}).ok);
  const Snapshot before(m);
  EXPECT_EQ(m.collapse_edge(Keep{0}, Remove{1}, nullptr), OpStatus::LinkCondition);
  EXPECT_TRUE(Snapshot(m) == before);
}

TEST(CollapseEdge, RefusesInversionAndKeepsTheMesh) {
  TetMesh m = two_tets();
  index_t c = -1;
  ASSERT_EQ(m.split_face(0, 3, nullptr, &c), OpStatus::Ok);  // interior vertex c
  const Snapshot before(m);
  const Vec3 far(0.3, 0.3, 5.0);
  EXPECT_EQ(m.collapse_edge(Keep{c}, Remove{0}, &far), OpStatus::Inverted);
  EXPECT_TRUE(Snapshot(m) == before);
  // Collapsing c onto vertex 0 keeps a valid mesh of the two original tets'
  // union: back to ... four tets? No: c's six tets lose the two on edge (c, 0).
  ASSERT_EQ(m.half_edge_collapse(Keep{0}, Remove{c}), OpStatus::Ok);
  EXPECT_EQ(tet_sets(m), sorted_sets({{0, 1, 2, 3}, {0, 1, 2, 4}}));
  expect_valid(m);
}

// The face matching runs in parallel from kParallelMinItems tets on; the
// mesh it builds (tets, neighbours across each face, vertex classes) does
// not depend on the number of threads.
TEST(TetMeshBuild, DoesNotDependOnThreadCount) {
  const testing::TestMesh cube = testing::make_cube_mesh(13, 0.2, 3);
  ASSERT_GE(static_cast<long>(cube.tets.size()), kParallelMinItems);
  TetMesh meshes[3];
  for (int k = 0; k < 3; ++k) {
    BuildOptions options;
    options.face_regions = cube.face_regions;
    ASSERT_TRUE(testing::with_threads(k + 1, [&] { return meshes[k].build(cube.points, cube.tets, options); }).ok);
  }
  for (int k = 1; k < 3; ++k) {
    ASSERT_EQ(meshes[k].tet_slots(), meshes[0].tet_slots());
    for (index_t t = 0; t < meshes[0].tet_slots(); ++t) {
      ASSERT_EQ(meshes[k].tet(t), meshes[0].tet(t));
      for (int f = 0; f < 4; ++f) ASSERT_EQ(meshes[k].adjacency(t, f), meshes[0].adjacency(t, f)) << t << " " << f;
    }
    for (index_t v = 0; v < meshes[0].vertex_slots(); ++v)
      ASSERT_EQ(meshes[k].vertex_class(v), meshes[0].vertex_class(v));
  }
  expect_valid(meshes[2]);
}

// The split with the ring given (as Density control passes it) makes the
// same mesh as the one that walks it, slot for slot, on interior and
// boundary edges.
TEST(SplitEdge, GivenRingGivesTheSameMesh) {
  const testing::TestMesh cube = testing::make_cube_mesh(3, 0.2, 5);
  TetMesh plain, given;
  ASSERT_TRUE(plain.build(cube.points, cube.tets).ok);
  ASSERT_TRUE(given.build(cube.points, cube.tets).ok);
  std::vector<index_t> ring, opposite, neighbours;
  std::size_t splits[2] = {0, 0};  // interior, boundary
  const index_t n = plain.vertex_slots();
  for (index_t a = 0; a < n; a += 3) {
    plain.vertex_neighbors(a, neighbours);
    const index_t b = neighbours.front();
    bool boundary = false;
    ASSERT_TRUE(given.edge_ring_with_vertices(a, b, ring, opposite, &boundary));
    index_t v1 = -1, v2 = -1;
    ASSERT_EQ(plain.split_edge(a, b, nullptr, &v1), OpStatus::Ok);
    ASSERT_EQ(given.split_edge(a, b, nullptr, &v2, ring, opposite, boundary), OpStatus::Ok);
    EXPECT_EQ(v1, v2);
    EXPECT_EQ(plain.vertex_class(v1), given.vertex_class(v2));
    ++splits[boundary];
  }
  EXPECT_GT(splits[0], 0u);
  EXPECT_GT(splits[1], 0u);
  ASSERT_EQ(plain.tet_slots(), given.tet_slots());
  for (index_t t = 0; t < plain.tet_slots(); ++t) {
    EXPECT_EQ(plain.tet(t), given.tet(t));
    for (int f = 0; f < 4; ++f) EXPECT_EQ(plain.adjacency(t, f), given.adjacency(t, f));
  }
  expect_valid(given);
}

// The edge removal into a fan makes the mesh of a split followed by the
// collapse of the new vertex into the apex, and refuses where that
// collapse is refused (an edge it would make exists already, or a tet
// would invert), leaving the mesh as it was.
TEST(FlipEdgeToFan, MatchesSplitThenCollapse) {
  const testing::TestMesh cube = testing::make_cube_mesh(4, 0.2, 11);
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(cube.points, cube.tets).ok);
  std::vector<index_t> ring, opposite, neighbours;
  std::size_t done = 0, refused = 0;
  for (index_t a = 0; a < mesh.vertex_slots(); ++a) {
    if (mesh.on_boundary(a)) continue;
    mesh.vertex_neighbors(a, neighbours);
    for (const index_t b : neighbours) {
      if (b < a || mesh.on_boundary(b)) continue;
      bool boundary = false;
      ASSERT_TRUE(mesh.edge_ring_with_vertices(a, b, ring, opposite, &boundary));
      ASSERT_FALSE(boundary);
      for (const index_t apex : opposite) {
        TetMesh split = mesh, fan = mesh;
        index_t m = -1;
        ASSERT_EQ(split.split_edge(a, b, nullptr, &m), OpStatus::Ok);
        const bool collapsed = split.half_edge_collapse(Keep{apex}, Remove{m}) == OpStatus::Ok;
        const Snapshot before(fan);
        const OpStatus s = fan.flip_edge_to_fan(a, b, apex, ring, opposite);
        EXPECT_EQ(s == OpStatus::Ok, collapsed) << "edge " << a << "-" << b << " apex " << apex;
        if (s == OpStatus::Ok && collapsed) {
          ++done;
          EXPECT_EQ(tet_sets(fan), tet_sets(split));
          EXPECT_FALSE(fan.has_edge(a, b));
          expect_valid(fan);
        } else if (s != OpStatus::Ok) {
          ++refused;
          EXPECT_TRUE(Snapshot(fan) == before);
        }
      }
    }
  }
  EXPECT_GT(done, 100u);
  EXPECT_GT(refused, 10u);
}

// The collapse with the balls given (as Density control passes them) makes
// the same mesh as the one that walks them, slot for slot, and refuses alike.
TEST(CollapseEdge, GivenBallsGiveTheSameMesh) {
  const testing::TestMesh cube = testing::make_cube_mesh(3, 0.2, 7);
  TetMesh plain, given;
  ASSERT_TRUE(plain.build(cube.points, cube.tets).ok);
  ASSERT_TRUE(given.build(cube.points, cube.tets).ok);
  std::size_t done = 0, refused = 0;
  std::vector<index_t> ball_keep, ball_remove;
  for (index_t a = 0; a < plain.vertex_slots(); ++a) {
    std::vector<index_t> neighbours;
    if (!plain.vertex_alive(a)) continue;
    plain.vertex_neighbors(a, neighbours);
    for (const index_t b : neighbours) {
      if (!plain.vertex_alive(b) || !plain.has_edge(a, b)) continue;
      const Vec3 mid = 0.5 * (plain.point(a) + plain.point(b));
      given.vertex_ball(a, ball_keep);
      given.vertex_ball(b, ball_remove);
      const OpStatus s1 = plain.collapse_edge(Keep{a}, Remove{b}, &mid);
      const OpStatus s2 = given.collapse_edge(Keep{a}, Remove{b}, &mid, ball_keep, ball_remove);
      ASSERT_EQ(s1, s2);
      (s1 == OpStatus::Ok ? done : refused) += 1;
      break;
    }
  }
  EXPECT_GT(done, 5u);
  EXPECT_GT(refused, 0u);
  ASSERT_EQ(plain.tet_slots(), given.tet_slots());
  for (index_t t = 0; t < plain.tet_slots(); ++t) {
    ASSERT_EQ(plain.tet_alive(t), given.tet_alive(t));
    if (plain.tet_alive(t)) {
      EXPECT_EQ(plain.tet(t), given.tet(t));
    }
  }
  expect_valid(given);
}

TEST(CollapseEdge, CheckThenCollapseMatchesCollapseEdge) {
  // check_collapse (read only, the caller's stamps) refuses exactly what
  // collapse_edge refuses, and collapse_checked_edge then changes the mesh
  // as collapse_edge does; at the midpoint and at keep's position.
  for (const bool half : {false, true}) {
    const testing::TestMesh cube = testing::make_cube_mesh(3, 0.2, 7);
    TetMesh plain, checked;
    ASSERT_TRUE(plain.build(cube.points, cube.tets).ok);
    ASSERT_TRUE(checked.build(cube.points, cube.tets).ok);
    std::size_t done = 0;
    std::map<OpStatus, std::size_t> refused;
    std::vector<index_t> ball_keep, ball_remove, neighbours;
    TetMesh::VertexStamps stamps;
    for (index_t a = 0; a < plain.vertex_slots(); ++a) {
      if (!plain.vertex_alive(a)) continue;
      plain.vertex_neighbors(a, neighbours);
      for (const index_t b : neighbours) {
        if (!plain.vertex_alive(b) || !plain.has_edge(a, b)) continue;
        const Vec3 p = half ? plain.point(a) : Vec3(0.5 * (plain.point(a) + plain.point(b)));
        checked.vertex_ball(a, ball_keep);
        checked.vertex_ball(b, ball_remove);
        const OpStatus s1 = plain.collapse_edge(Keep{a}, Remove{b}, &p);
        const OpStatus s2 = checked.check_collapse(Keep{a}, Remove{b}, p, ball_keep, ball_remove, stamps);
        ASSERT_EQ(s1, s2);
        if (s2 == OpStatus::Ok) {
          ASSERT_EQ(checked.collapse_checked_edge(Keep{a}, Remove{b}, p, ball_keep, ball_remove), OpStatus::Ok);
          ++done;
        } else {
          ++refused[s2];
        }
        if (s1 == OpStatus::Ok) break;
      }
    }
    EXPECT_GT(done, 5u);
    EXPECT_GT(refused[OpStatus::LinkCondition], 0u);
    EXPECT_GT(refused[OpStatus::Inverted], 0u);
    ASSERT_EQ(plain.tet_slots(), checked.tet_slots());
    for (index_t t = 0; t < plain.tet_slots(); ++t) {
      ASSERT_EQ(plain.tet_alive(t), checked.tet_alive(t));
      if (plain.tet_alive(t)) {
        EXPECT_EQ(plain.tet(t), checked.tet(t));
      }
    }
    for (index_t v = 0; v < plain.vertex_slots(); ++v) {
      ASSERT_EQ(plain.vertex_alive(v), checked.vertex_alive(v));
      if (plain.vertex_alive(v)) {
        EXPECT_EQ(plain.point(v), checked.point(v));
        EXPECT_EQ(plain.vertex_class(v), checked.vertex_class(v));
      }
    }
    EXPECT_TRUE(checked.check_consistency().ok);
    expect_valid(checked);
  }
}

// ---------------------------------------------------------------------------
// The cube cut into 2 x 2 x 2 cells, faces in six regions: vertex classes and
// the collapse rules of thesis Fig. 2.37.
class CollapseRules : public ::testing::Test {
 protected:
  void SetUp() override {
    cube = testing::make_cube_mesh(2, 0.0, 1);
    BuildOptions opt;
    opt.face_regions = cube.face_regions;
    ASSERT_TRUE(m.build(cube.points, cube.tets, opt).ok);
  }
  index_t id(int i, int j, int k) const { return (k * 3 + j) * 3 + i; }
  testing::TestMesh cube;
  TetMesh m;
};

TEST_F(CollapseRules, VertexClasses) {
  EXPECT_EQ(m.vertex_class(id(0, 0, 0)), VertexClass::Corner);
  EXPECT_EQ(m.vertex_class(id(1, 0, 0)), VertexClass::Curve);
  EXPECT_EQ(m.vertex_class(id(1, 1, 0)), VertexClass::Surface);
  EXPECT_EQ(m.vertex_class(id(1, 1, 1)), VertexClass::Inner);
  EXPECT_TRUE(m.is_curve_edge(id(0, 0, 0), id(1, 0, 0)));
  EXPECT_FALSE(m.is_curve_edge(id(1, 0, 0), id(1, 1, 0)));
}

TEST_F(CollapseRules, ForbiddenEdges) {
  // Kuhn cells have the diagonals (i,j,k)-(i+1,j+1,k) etc. on their faces.
  // (A) corner-corner: no such edge at n = 2; (B) curve-curve off the curve:
  // (1,0,0)-(2,1,0)? (2,1,0) is a curve vertex of edge x=1,z=0.
  ASSERT_TRUE(m.has_edge(id(1, 0, 0), id(2, 1, 0)));
  EXPECT_EQ(m.plan_collapse_by_rules(id(1, 0, 0), id(2, 1, 0)).status, OpStatus::ForbiddenByRule);
  // (C) interior edge between two surface vertices: (1,1,0)-(1,1,... none;
  // take the interior diagonal from face centre (1,1,0) to edge vertex
  // (2,2,1) if present, else from (0,1,1) to (1,2,2)... use any such edge.
  int interior_surface_edges = 0;
  for (index_t a = 0; a < 27; ++a)
    for (index_t b = a + 1; b < 27; ++b) {
      if (!m.has_edge(a, b) || m.vertex_class(a) == VertexClass::Inner || m.vertex_class(b) == VertexClass::Inner)
        continue;
      std::vector<index_t> ring;
      bool on_boundary = false;
      m.edge_ring(a, b, ring, &on_boundary);
      if (on_boundary) continue;
      ++interior_surface_edges;
      EXPECT_EQ(m.plan_collapse_by_rules(a, b).status, OpStatus::ForbiddenByRule);
    }
  EXPECT_GT(interior_surface_edges, 0);
}

TEST_F(CollapseRules, PositionsFollowTheMoreConstrainedVertex) {
  // (D) corner-curve along the curve: keeps the corner.
  CollapsePlan p = m.plan_collapse_by_rules(id(1, 0, 0), id(0, 0, 0));
  ASSERT_EQ(p.status, OpStatus::Ok);
  EXPECT_EQ(p.keep, id(0, 0, 0));
  EXPECT_TRUE(p.position.isApprox(Vec3(0, 0, 0)));
  // (E) curve-surface: keeps the curve vertex.
  p = m.plan_collapse_by_rules(id(1, 1, 0), id(1, 0, 0));
  ASSERT_EQ(p.status, OpStatus::Ok);
  EXPECT_EQ(p.keep, id(1, 0, 0));
  // (F) surface-inner: keeps the surface vertex.
  p = m.plan_collapse_by_rules(id(1, 1, 1), id(1, 1, 0));
  ASSERT_EQ(p.status, OpStatus::Ok);
  EXPECT_EQ(p.keep, id(1, 1, 0));
  EXPECT_TRUE(p.position.isApprox(Vec3(0.5, 0.5, 0)));
  // Collapse it: volume and boundary kept.
  const double v0 = volume(m);
  index_t kept = -1;
  ASSERT_EQ(m.collapse_edge_by_rules(id(1, 1, 1), id(1, 1, 0), &kept), OpStatus::Ok);
  EXPECT_EQ(kept, id(1, 1, 0));
  EXPECT_NEAR(volume(m), v0, 1e-14);
  EXPECT_FALSE(m.vertex_alive(id(1, 1, 1)));
  expect_valid(m);
}

TEST_F(CollapseRules, SurfaceEdgeFlip) {
  // On face z = 0 the Kuhn diagonal of cell (0,0) is (0,0,0)-(1,1,0); its two
  // boundary triangles have apexes (1,0,0) and (0,1,0).
  const index_t a = id(0, 0, 0), b = id(1, 1, 0), c = id(1, 0, 0), d = id(0, 1, 0);
  ASSERT_TRUE(m.has_edge(a, b));
  ASSERT_FALSE(m.has_edge(c, d));
  const double v0 = volume(m);
  const std::size_t nb = boundary_faces(m), nt = m.live_tets();
  ASSERT_EQ(m.flip_surface_edge(a, b), OpStatus::Ok);
  EXPECT_TRUE(m.has_edge(c, d));
  EXPECT_FALSE(m.has_edge(a, b));
  EXPECT_EQ(boundary_faces(m), nb);
  EXPECT_EQ(m.live_vertices(), 27u);
  EXPECT_GE(m.live_tets(), nt - 1);
  EXPECT_NEAR(volume(m), v0, 1e-14);
  expect_valid(m);
  // A curve edge cannot be flipped this way.
  EXPECT_EQ(m.flip_surface_edge(id(0, 0, 0), id(1, 0, 0)), OpStatus::ForbiddenByRule);
}

}  // namespace
}  // namespace femorph

namespace femorph {
namespace {

/// Mean distance between consecutive live points (dead slots skipped).
double mean_step(const std::vector<Vec3>& p, const TetMesh* alive = nullptr) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t v = 1; v < p.size(); ++v) {
    if (alive && (!alive->vertex_alive(static_cast<index_t>(v)) || !alive->vertex_alive(static_cast<index_t>(v - 1))))
      continue;
    sum += (p[v] - p[v - 1]).norm();
    ++n;
  }
  return sum / static_cast<double>(n);
}

// TetMesh::sort_spatially: after edits that leave dead and reused slots, the
// renumbered mesh is the same mesh (tets by coordinates, face regions,
// classes, provenance), dense, consistent, and its slots follow space.
TEST(SortSpatially, SameMeshDenseAndInSpaceOrder) {
  const testing::TestMesh cube = testing::make_cube_mesh(6, 0.1, 4);
  TetMesh mesh;
  BuildOptions bo;
  bo.face_regions = cube.face_regions;
  ASSERT_TRUE(mesh.build(cube.points, cube.tets, bo).ok);
  // Edits: splits append, collapses free slots that later splits reuse.
  std::size_t collapsed = 0;
  for (index_t a = 0; a < 200; a += 3) {
    std::vector<index_t> nb;
    if (!mesh.vertex_alive(a)) continue;
    mesh.vertex_neighbors(a, nb);
    index_t v;
    mesh.split_edge(a, nb.front(), nullptr, &v);
    const Vec3 mid = 0.5 * (mesh.point(a) + mesh.point(nb.back()));
    collapsed += mesh.collapse_edge(Keep{a}, Remove{nb.back()}, &mid) == OpStatus::Ok;
  }
  ASSERT_GT(collapsed, 10u);
  ASSERT_TRUE(mesh.check_consistency().ok);
  // Everything about a tet that must survive, keyed by its corner positions.
  using Key = std::array<std::array<double, 3>, 4>;
  struct Facts {
    std::array<index_t, 4> regions;  // by sorted corner
    index_t origin;
  };
  const auto facts = [](const TetMesh& m) {
    std::map<Key, Facts> out;
    for (index_t t = 0; t < m.tet_slots(); ++t) {
      if (!m.tet_alive(t)) continue;
      std::array<std::pair<std::array<double, 3>, int>, 4> corners;
      for (int i = 0; i < 4; ++i) {
        const Vec3& p = m.point(m.tet(t)[i]);
        corners[i] = {{p.x(), p.y(), p.z()}, i};
      }
      std::sort(corners.begin(), corners.end());
      Key key;
      Facts f;
      for (int i = 0; i < 4; ++i) {
        key[i] = corners[i].first;
        f.regions[i] = m.face_region(t, corners[i].second);
      }
      f.origin = m.tet_origin(t);
      EXPECT_TRUE(out.emplace(key, f).second);
    }
    return out;
  };
  const auto vertex_facts = [](const TetMesh& m) {
    std::map<std::array<double, 3>, std::pair<VertexClass, index_t>> out;
    for (index_t v = 0; v < m.vertex_slots(); ++v)
      if (m.vertex_alive(v))
        out[{m.point(v).x(), m.point(v).y(), m.point(v).z()}] = {m.vertex_class(v), m.vertex_origin(v).ids[0]};
    return out;
  };
  const auto before = facts(mesh);
  const auto before_vertices = vertex_facts(mesh);
  const std::vector<Vec3> old_points = mesh.points();
  const std::size_t live_tets = mesh.live_tets();
  ASSERT_GT(static_cast<std::size_t>(mesh.tet_slots()), live_tets);  // dead slots to drop

  const TetMesh before_mesh = mesh;
  const std::vector<index_t> map = mesh.sort_spatially();
  ASSERT_TRUE(mesh.check_consistency().ok) << mesh.check_consistency().message;
  expect_valid(mesh);
  EXPECT_EQ(static_cast<std::size_t>(mesh.tet_slots()), live_tets);
  EXPECT_EQ(static_cast<std::size_t>(mesh.vertex_slots()), before_vertices.size());
  for (index_t v = 0; v < static_cast<index_t>(map.size()); ++v)
    if (map[v] >= 0) {
      EXPECT_EQ(mesh.point(map[v]), old_points[v]);
    }
  const auto after = facts(mesh);
  ASSERT_EQ(after.size(), before.size());
  for (const auto& [key, f] : before) {
    const auto it = after.find(key);
    ASSERT_NE(it, after.end());
    EXPECT_EQ(it->second.regions, f.regions);
    EXPECT_EQ(it->second.origin, f.origin);
  }
  EXPECT_EQ(vertex_facts(mesh), before_vertices);
  // In space order: consecutive vertices closer than before (the split
  // vertices were appended far from their neighbours), tets by lowest vertex.
  const double step_before = mean_step(old_points, &before_mesh), step_after = mean_step(mesh.points());
  std::printf("mean distance of consecutive vertices: %.3f -> %.3f\n", step_before, step_after);
  EXPECT_LT(step_after, 0.8 * step_before);
  index_t lowest = 0;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    const Tet& T = mesh.tet(t);
    const index_t m = *std::min_element(T.begin(), T.end());
    EXPECT_GE(m, lowest);
    lowest = m;
  }
  // New edits work on the renumbered mesh.
  index_t v;
  std::vector<index_t> nb;
  mesh.vertex_neighbors(0, nb);
  EXPECT_EQ(mesh.split_edge(0, nb.front(), nullptr, &v), OpStatus::Ok);
  expect_valid(mesh);
}

}  // namespace
}  // namespace femorph
