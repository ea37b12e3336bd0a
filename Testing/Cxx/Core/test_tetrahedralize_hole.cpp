// Thesis 3.5.5, the contact case's refill: a ball of tets (space and object)
// is cut out of a block-in-box mesh, the hole's facets (its boundary and the
// object's surface inside it) are refilled by TetGen, and the refill is
// spliced back. The mesh must stay valid with every facet whole, no point on
// a facet, and each material's volume unchanged; bad holes fail with a
// message.
#include "adapt/adapt.h"
#include "geometry/predicates.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "test_adapt_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace femorph {
namespace {

using testing::make_block_in_box;
using testing::MaterialMesh;
using Key = std::array<index_t, 3>;

Key sorted_key(const std::array<index_t, 3>& v) {
  Key k = v;
  std::sort(k.begin(), k.end());
  return k;
}

double volume(const std::vector<Vec3>& p, const Tet& t) { return tet_signed_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]); }

/// Distance from p to the triangle (a, b, c) (closest point by regions).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

/// Radius-edge ratio: circumradius over the shortest edge (sqrt(6)/4 for the
/// regular tet).
double radius_edge_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u = b - a, v = c - a, w = d - a;
  const Vec3 centre =
      (u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u) + w.squaredNorm() * u.cross(v)) / (2 * u.dot(v.cross(w)));
  double shortest = 1e300;
  const Vec3* p[4] = {&a, &b, &c, &d};
  for (const auto& e : kTetEdge) shortest = std::min(shortest, (*p[e[0]] - *p[e[1]]).norm());
  return centre.norm() / shortest;
}

/// A block-in-box mesh as a TetMesh, with the material by tet origin.
struct Case {
  MaterialMesh input;
  TetMesh mesh;
};

void build_case(Case& c, std::array<int, 3> cells, std::array<int, 3> object, std::array<int, 3> offset) {
  c.input = make_block_in_box(cells, object, 1.0, 0.2, 17, offset);
  ASSERT_TRUE(c.mesh.build(c.input.points, c.input.tets).ok);
}

/// The tets whose centroid lies in the shell r_in <= |x - centre| < r_out,
/// grown until the hole's boundary is edge-manifold (the tets around an edge
/// on more than two of its faces join the hole).
std::vector<index_t> cut_ball(const Case& c, const Vec3& centre, double r_in, double r_out) {
  const TetMesh& mesh = c.mesh;
  std::set<index_t> removed;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    const Tet& T = mesh.tet(t);
    const Vec3 g = 0.25 * (mesh.point(T[0]) + mesh.point(T[1]) + mesh.point(T[2]) + mesh.point(T[3]));
    const double r = (g - centre).norm();
    if (r >= r_in && r < r_out) removed.insert(t);
  }
  const auto material = [&](index_t t) { return c.input.material[mesh.tet_origin(t)]; };
  for (;;) {
    const std::vector<index_t> list(removed.begin(), removed.end());
    std::map<std::pair<index_t, index_t>, int> count;
    for (const HoleFacet& f : hole_facets(mesh, list, material))
      if (f.front == -1 || f.back == -1)
        for (int i = 0; i < 3; ++i) ++count[std::minmax(f.v[i], f.v[(i + 1) % 3])];
    bool grown = false;
    for (const auto& [e, n] : count)
      if (n != 2) {
        std::vector<index_t> ring;
        bool open = false;
        EXPECT_TRUE(mesh.edge_ring(e.first, e.second, ring, &open));
        for (const index_t t : ring) grown = removed.insert(t).second || grown;
      }
    if (!grown) return list;
  }
}

struct Volumes {
  double total = 0;
  std::map<int, double> by_material;
};

Volumes mesh_volumes(const TetMesh& mesh, const std::vector<int>& material_by_origin) {
  Volumes v;
  for (index_t t = 0; t < mesh.tet_slots(); ++t)
    if (mesh.tet_alive(t)) {
      const double x = volume(mesh.points(), mesh.tet(t));
      v.total += x;
      v.by_material[material_by_origin[mesh.tet_origin(t)]] += x;
    }
  return v;
}

/// Cuts the shell out of the case, refills it, checks the refill and splices
/// it back; then checks the whole mesh.
void refill_and_check(Case& c, const Vec3& centre, double r_in, double r_out, bool expect_new_points = false) {
  TetMesh& mesh = c.mesh;
  const std::vector<int>& material_by_origin = c.input.material;
  const auto material = [&](index_t t) { return material_by_origin[mesh.tet_origin(t)]; };
  const std::vector<index_t> removed = cut_ball(c, centre, r_in, r_out);
  const std::vector<HoleFacet> facets = hole_facets(mesh, removed, material);
  std::size_t interfaces = 0;
  std::set<int> hole_materials;
  for (const index_t t : removed) hole_materials.insert(material(t));
  for (const HoleFacet& f : facets) interfaces += f.front >= 0 && f.back >= 0;
  // The ball crosses the object's surface: both materials and interfaces.
  ASSERT_EQ(hole_materials.size(), 2u);
  ASSERT_GT(interfaces, 0u);
  const Volumes before = mesh_volumes(mesh, material_by_origin);

  std::vector<Vec3> points = mesh.points();
  const std::size_t n0 = points.size();
  std::vector<Tet> tets;
  std::vector<int> tet_material;
  const Status s = tetrahedralize_hole(points, facets, 1.4, tets, tet_material);
  ASSERT_TRUE(s.ok) << s.message;
  ASSERT_EQ(tets.size(), tet_material.size());
  if (expect_new_points) {
    EXPECT_GT(points.size(), n0);
  }
  std::printf("hole: %zu tets removed (%zu facets, %zu interfaces) -> %zu tets, %zu new points\n", removed.size(),
              facets.size(), interfaces, tets.size(), points.size() - n0);

  // The refill: positive, each material's volume the removed one's.
  std::map<int, double> removed_volume, refill_volume;
  for (const index_t t : removed) removed_volume[material(t)] += volume(mesh.points(), mesh.tet(t));
  double min_stretch = 1, max_ratio = 0, removed_min_stretch = 1, removed_max_ratio = 0;
  for (const index_t t : removed) {
    const Tet& T = mesh.tet(t);
    const Vec3 &a = mesh.point(T[0]), &b = mesh.point(T[1]), &cc = mesh.point(T[2]), &d = mesh.point(T[3]);
    removed_min_stretch = std::min(removed_min_stretch, tet_stretch(a, b, cc, d));
    removed_max_ratio = std::max(removed_max_ratio, radius_edge_ratio(a, b, cc, d));
  }
  for (std::size_t i = 0; i < tets.size(); ++i) {
    const Tet& T = tets[i];
    ASSERT_EQ(orient3d_sign(points[T[0]], points[T[1]], points[T[2]], points[T[3]]), 1);
    refill_volume[tet_material[i]] += volume(points, T);
    min_stretch = std::min(min_stretch, tet_stretch(points[T[0]], points[T[1]], points[T[2]], points[T[3]]));
    max_ratio = std::max(max_ratio, radius_edge_ratio(points[T[0]], points[T[1]], points[T[2]], points[T[3]]));
  }
  std::printf("refill: min stretch %.3f, max radius-edge ratio %.3f (removed tets: %.3f, %.3f)\n", min_stretch,
              max_ratio, removed_min_stretch, removed_max_ratio);
  ASSERT_EQ(refill_volume.size(), removed_volume.size());
  for (const auto& [m, v] : removed_volume) EXPECT_NEAR(refill_volume[m], v, 1e-9 * v) << "material " << m;
  // Quality near the removed tets' (the 12-tet cubes'): -q bounds the ratio
  // inside; next to the facets, which TetGen may not split, it cannot.
  EXPECT_GT(min_stretch, 0.5 * removed_min_stretch);
  EXPECT_LT(max_ratio, 1.5 * removed_max_ratio);

  // Every facet is a face of the refill: a boundary facet of one tet, an
  // interface of two; no new point lies on (or near) a facet.
  std::map<Key, int> face_count;
  for (const Tet& T : tets)
    for (const auto& f : kTetFace) ++face_count[sorted_key({{T[f[0]], T[f[1]], T[f[2]]}})];
  for (const HoleFacet& f : facets) {
    const bool boundary = f.front == -1 || f.back == -1;
    EXPECT_EQ(face_count[sorted_key(f.v)], boundary ? 1 : 2);
  }
  for (std::size_t i = n0; i < points.size(); ++i)
    for (const HoleFacet& f : facets)
      ASSERT_GT(point_triangle_distance(points[i], points[f.v[0]], points[f.v[1]], points[f.v[2]]), 1e-6)
          << "new point " << i << " lies on a facet";

  // Splice: new points as negative ids, each new tet descends from a removed
  // tet of its material (so its material by origin is right).
  std::map<int, index_t> origin_of;
  for (const index_t t : removed) origin_of.emplace(material(t), mesh.tet_origin(t));
  std::vector<Tet> new_tets = tets;
  for (Tet& T : new_tets)
    for (index_t& v : T)
      if (v >= static_cast<index_t>(n0)) v = -1 - (v - static_cast<index_t>(n0));
  std::vector<index_t> origins;
  for (const int m : tet_material) origins.push_back(origin_of.at(m));
  const std::vector<Vec3> new_points(points.begin() + static_cast<std::ptrdiff_t>(n0), points.end());
  std::vector<VertexStencil> stencils(new_points.size());
  for (VertexStencil& st : stencils) {
    st.ids[0] = facets[0].v[0];
    st.weights[0] = 1;
  }
  const Status spliced = mesh.replace_cavity(removed, new_tets, origins, new_points, stencils);
  ASSERT_TRUE(spliced.ok) << spliced.message;
  const Status consistent = mesh.check_consistency();
  ASSERT_TRUE(consistent.ok) << consistent.message;
  const CompactMesh out = mesh.compact();
  const ValidityReport report = check_validity(out.points, out.tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  const Volumes after = mesh_volumes(mesh, material_by_origin);
  EXPECT_NEAR(after.total, before.total, 1e-9 * before.total);
  ASSERT_EQ(after.by_material.size(), before.by_material.size());
  for (const auto& [m, v] : before.by_material) EXPECT_NEAR(after.by_material.at(m), v, 1e-9 * v) << "material " << m;
}

TEST(TetrahedralizeHole, ABallAcrossTheObjectsSurfaceIsRefilledKeepingTheFacets) {
  Case c;
  build_case(c, {{6, 6, 6}}, {{2, 2, 2}}, {{-1, -1, -1}});
  // Centred on the object's face x = 2, reaching an edge of the block.
  refill_and_check(c, Vec3(2.1, 2.6, 3.0), 0, 1.6);
}

TEST(TetrahedralizeHole, ALargeBallGetsSteinerPointsInsideOnly) {
  Case c;
  // Wide enough that -q inserts points inside the hole: they must stay off
  // the facets and splice in as new vertices.
  build_case(c, {{9, 9, 9}}, {{4, 4, 4}}, {{-1, -1, -1}});
  refill_and_check(c, Vec3(2.5, 4.3, 4.6), 0, 3.2, /*expect_new_points=*/true);
}

TEST(TetrahedralizeHole, AHoleOnTheOuterBoundaryIsRefilled) {
  Case c;
  // The object touches the box's face x = 0; the ball reaches it.
  build_case(c, {{5, 5, 5}}, {{2, 2, 2}}, {{0, 1, 1}});
  refill_and_check(c, Vec3(1.0, 1.1, 2.0), 0, 1.5);
}

TEST(TetrahedralizeHole, AShellAroundKeptTetsIsRefilledAroundThem) {
  Case c;
  // The kept tets inside the shell are a void TetGen meshes too: the refill
  // must drop them (their facet sides say -1).
  build_case(c, {{6, 6, 6}}, {{2, 2, 2}}, {{-1, -1, -1}});
  refill_and_check(c, Vec3(2.0, 3.0, 3.0), 0.8, 2.0);
}

/// The facets of a ball hole, for the failure tests.
struct HoleCase {
  Case c;
  std::vector<HoleFacet> facets;
};

void build_hole(HoleCase& h) {
  build_case(h.c, {{5, 5, 5}}, {{2, 2, 2}}, {{-1, -1, -1}});
  const std::vector<index_t> removed = cut_ball(h.c, Vec3(2.0, 2.5, 2.5), 0, 1.4);
  h.facets = hole_facets(h.c.mesh, removed,
                         [&](index_t t) { return h.c.input.material[h.c.mesh.tet_origin(t)]; });
}

Status refill(const HoleCase& h, const std::vector<HoleFacet>& facets, std::vector<Vec3>* points_out = nullptr) {
  std::vector<Vec3> points = h.c.mesh.points();
  std::vector<Tet> tets;
  std::vector<int> material;
  const Status s = tetrahedralize_hole(points, facets, 1.4, tets, material);
  if (points_out) *points_out = points;
  return s;
}

TEST(TetrahedralizeHole, BadHolesFailWithAMessage) {
  HoleCase h;
  build_hole(h);
  ASSERT_TRUE(refill(h, h.facets).ok);
  const auto expect_failure = [&](const std::vector<HoleFacet>& facets, const char* what) {
    std::vector<Vec3> points;
    const Status s = refill(h, facets, &points);
    EXPECT_FALSE(s.ok) << what;
    EXPECT_NE(s.message.find(what), std::string::npos) << s.message;
    EXPECT_EQ(points.size(), h.c.mesh.points().size()) << "no point added on failure";
  };
  // Open: one boundary facet dropped.
  std::vector<HoleFacet> f = h.facets;
  const auto first_boundary = std::find_if(f.begin(), f.end(), [](const HoleFacet& x) { return x.front == -1; });
  ASSERT_NE(first_boundary, f.end());
  f.erase(first_boundary);
  expect_failure(f, "open hole boundary");
  // A boundary facet with its sides swapped.
  f = h.facets;
  for (HoleFacet& x : f)
    if (x.front == -1) {
      std::swap(x.front, x.back);
      break;
    }
  expect_failure(f, "disagree");
  // No interface: the object's and the space's sides meet in one region.
  f.clear();
  for (const HoleFacet& x : h.facets)
    if (x.front == -1 || x.back == -1) f.push_back(x);
  ASSERT_LT(f.size(), h.facets.size());
  expect_failure(f, "materials 0 and 1");
  // A repeated facet, a facet on one point twice, a degenerate one (a point
  // on an edge's midpoint, collinear).
  f = h.facets;
  f.push_back(f[0]);
  expect_failure(f, "repeats facet");
  f = h.facets;
  f[0].v[1] = f[0].v[0];
  expect_failure(f, "repeats a point");
  f = h.facets;
  f.push_back({{{f[0].v[0], f[0].v[1], f[1].v[2]}}, -1, 0});  // sanity: a non-manifold extra facet
  EXPECT_FALSE(refill(h, f).ok);
  f = h.facets;
  f.push_back({{{-1, f[0].v[1], f[0].v[2]}}, -1, 0});
  expect_failure(f, "out of range");
  // The ratio is checked.
  std::vector<Vec3> points = h.c.mesh.points();
  std::vector<Tet> tets;
  std::vector<int> material;
  const Status low = tetrahedralize_hole(points, h.facets, 0.5, tets, material);
  EXPECT_FALSE(low.ok);
  EXPECT_NE(low.message.find("radius-edge ratio"), std::string::npos) << low.message;
}

TEST(TetrahedralizeHole, ADegenerateFacetFails) {
  // A tet's hole with one face replaced by a flat triangle: three collinear
  // points.
  std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  const std::vector<HoleFacet> facets = {
      {{{0, 1, 2}}, -1, 0}, {{{0, 3, 1}}, -1, 0}, {{{0, 4, 3}}, -1, 0}, {{{1, 3, 4}}, -1, 0}, {{{0, 1, 4}}, -1, 0}};
  std::vector<Tet> tets;
  std::vector<int> material;
  const Status s = tetrahedralize_hole(points, facets, 1.4, tets, material);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.message.find("degenerate"), std::string::npos) << s.message;
}

TEST(TetrahedralizeHole, ACubeWithAnInterfaceGetsBothMaterials) {
  // A unit cube cut by its diagonal plane x = y into materials 1 (x > y) and
  // 2: the smallest hole with an interface, its volumes exact.
  std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                         Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
  // Outward quads (normal out of the cube: front -1) split into triangles;
  // the halves' materials by which side of x = y the triangle lies.
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::vector<HoleFacet> facets;
  const auto inside = [&](std::array<index_t, 3> v) {
    const Vec3 g = (p[v[0]] + p[v[1]] + p[v[2]]) / 3;
    return g.x() > g.y() ? 1 : 2;
  };
  // Each quad split along its diagonal from q[0]: on the bottom and top
  // faces that is 0-2 and 4-6, in the plane x = y.
  for (const auto& q : quads)
    for (const std::array<index_t, 3> t : {std::array<index_t, 3>{{q[0], q[1], q[2]}}, std::array<index_t, 3>{{q[0], q[2], q[3]}}})
      facets.push_back({t, -1, inside(t)});
  // The interface: the rectangle 0 2 6 4, its normal (1, -1, 0) towards
  // material 1.
  facets.push_back({{{0, 2, 6}}, 1, 2});
  facets.push_back({{{0, 6, 4}}, 1, 2});
  std::vector<Tet> tets;
  std::vector<int> material;
  const std::size_t n0 = p.size();
  const Status s = tetrahedralize_hole(p, facets, 1.4, tets, material);
  ASSERT_TRUE(s.ok) << s.message;
  std::map<int, double> v;
  for (std::size_t i = 0; i < tets.size(); ++i) v[material[i]] += volume(p, tets[i]);
  EXPECT_NEAR(v[1], 0.5, 1e-12);
  EXPECT_NEAR(v[2], 0.5, 1e-12);
  EXPECT_GE(p.size(), n0);
}

/// A twisted triangular prism (top turned by 30 degrees), its sides split
/// along the diagonals that fold inwards (`schoenhardt`: Schönhardt's
/// polyhedron, which has no tetrahedrization on its own points) or outwards
/// (convex).
std::vector<HoleFacet> twisted_prism(std::vector<Vec3>& p, bool schoenhardt) {
  p.clear();
  for (int i = 0; i < 3; ++i) {
    const double a = degrees_to_radians(90 + 120 * i);
    p.emplace_back(std::cos(a), std::sin(a), 0);
  }
  for (int i = 0; i < 3; ++i) {
    const double a = degrees_to_radians(90 + 120 * i + 30);
    p.emplace_back(std::cos(a), std::sin(a), 1);
  }
  std::vector<std::array<index_t, 3>> tri = {{{0, 2, 1}}, {{3, 4, 5}}};
  for (index_t i = 0; i < 3; ++i) {
    const index_t j = (i + 1) % 3;
    if (schoenhardt) {
      tri.push_back({{i, j, 3 + j}});
      tri.push_back({{i, 3 + j, 3 + i}});
    } else {
      tri.push_back({{i, j, 3 + i}});
      tri.push_back({{j, 3 + j, 3 + i}});
    }
  }
  // Outward (normal away from the axis point at mid-height), material 3 in.
  const Vec3 centre(0, 0, 0.5);
  std::vector<HoleFacet> facets;
  for (auto t : tri) {
    const Vec3 n = (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
    const Vec3 g = (p[t[0]] + p[t[1]] + p[t[2]]) / 3;
    if (n.dot(g - centre) < 0) std::swap(t[1], t[2]);
    facets.push_back({t, -1, 3});
  }
  return facets;
}

TEST(TetrahedralizeHole, SchoenhardtsPrismGetsAPointInsideNotOnItsFacets) {
  for (const bool schoenhardt : {true, false}) {
    std::vector<Vec3> p;
    const std::vector<HoleFacet> facets = twisted_prism(p, schoenhardt);
    // The enclosed volume by the divergence theorem over the outward facets.
    double enclosed = 0;
    for (const HoleFacet& f : facets) enclosed += p[f.v[0]].dot(p[f.v[1]].cross(p[f.v[2]])) / 6;
    std::vector<Tet> tets;
    std::vector<int> material;
    const Status s = tetrahedralize_hole(p, facets, 1.4, tets, material);
    ASSERT_TRUE(s.ok) << s.message;
    double v = 0;
    for (const Tet& t : tets) v += volume(p, t);
    EXPECT_NEAR(v, enclosed, 1e-12);
    EXPECT_TRUE(std::all_of(material.begin(), material.end(), [](int m) { return m == 3; }));
    // Schönhardt's needs a Steiner point, inside.
    if (schoenhardt) {
      EXPECT_GE(p.size(), 7u);
    }
    for (std::size_t i = 6; i < p.size(); ++i)
      for (const HoleFacet& f : facets)
        EXPECT_GT(point_triangle_distance(p[i], p[f.v[0]], p[f.v[1]], p[f.v[2]]), 1e-3);
    std::printf("twisted prism (%s): %zu tets, %zu new points\n", schoenhardt ? "Schoenhardt" : "convex", tets.size(),
                p.size() - 6);
  }
}

TEST(TetrahedralizeHole, SelfIntersectingFacetsFailWithTetGensMessage) {
  // The convex twisted prism with a top corner pushed through the bottom:
  // the facets' topology is a closed surface, their geometry crosses itself.
  std::vector<Vec3> p;
  const std::vector<HoleFacet> facets = twisted_prism(p, false);
  p[3] = Vec3(0, 0, -0.5);
  std::vector<Tet> tets;
  std::vector<int> material;
  const Status s = tetrahedralize_hole(p, facets, 1.4, tets, material);
  EXPECT_FALSE(s.ok);
  // TetGen stops on the crossing (and, in Debian's 1.5.0, crashes after,
  // in its own process); its words name it.
  EXPECT_NE(s.message.find("TetGen"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("intersect"), std::string::npos) << s.message;
  std::printf("%s\n", s.message.c_str());
  EXPECT_EQ(p.size(), 6u);
  EXPECT_TRUE(tets.empty());
}

}  // namespace
}  // namespace femorph
