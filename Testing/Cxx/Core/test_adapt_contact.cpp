// Contact detection (thesis 3.4.2) on object surfaces whose overlap is known
// exactly: two boxes meeting on part of a face, a cylinder in a half tube.
#include "adapt/contact.h"

#include <gtest/gtest.h>

#include <cmath>

namespace femorph {
namespace {

// The surface of the box [lo, hi] cut into n x n squares per face (two
// triangles each), outward, appended to points and faces.
void box_surface(const Vec3& lo, const Vec3& hi, int n, std::vector<Vec3>& points, std::vector<Tri>& faces) {
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const index_t first = static_cast<index_t>(points.size());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          Vec3 p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
          p[v] = lo[v] + (hi[v] - lo[v]) * j / n;
          points.push_back(p);
        }
      const auto id = [&](int i, int j) { return first + j * (n + 1) + i; };
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          Tri a{{id(i, j), id(i + 1, j), id(i + 1, j + 1)}}, b{{id(i, j), id(i + 1, j + 1), id(i, j + 1)}};
          if (!side) {
            std::swap(a[1], a[2]);
            std::swap(b[1], b[2]);
          }
          faces.push_back(a);
          faces.push_back(b);
        }
    }
}

// Merges coincident points of one surface (the faces of a box share edges).
void weld(std::vector<Vec3>& points, std::vector<Tri>& faces, index_t from) {
  std::vector<index_t> map(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    map[i] = static_cast<index_t>(i);
    if (static_cast<index_t>(i) < from) continue;
    for (std::size_t j = static_cast<std::size_t>(from); j < i; ++j)
      if ((points[i] - points[j]).norm() < 1e-12) {
        map[i] = map[j];
        break;
      }
  }
  for (Tri& f : faces)
    for (index_t& v : f) v = map[v];
}

TEST(AdaptContact, TwoBoxesMeetOnPartOfAFace) {
  std::vector<Vec3> points;
  ObjectBoundary a, b;
  a.material = 1;
  b.material = 2;
  // The moving box is modelled at rest at [-3, -2] x [0, 1] x [0, 1]; its
  // pose translates it by +3 in x so its face x = 1 meets the fixed box's
  // face x = 1, which spans y in [0.25, 1.75].
  box_surface(Vec3(-3, 0, 0), Vec3(-2, 1, 1), 8, points, a.faces);
  weld(points, a.faces, 0);
  const index_t first_b = static_cast<index_t>(points.size());
  box_surface(Vec3(1, 0.25, 0), Vec3(2, 1.75, 1), 12, points, b.faces);
  weld(points, b.faces, first_b);
  ObjectSurfaceInfo ia, ib;
  ASSERT_TRUE(segment_object(points, a, ia));
  ASSERT_TRUE(segment_object(points, b, ib));
  ASSERT_EQ(ia.regions.size(), 6u);
  ASSERT_EQ(ib.regions.size(), 6u);
  RigidPose pose;
  pose.t = Vec3(3, 0, 0);
  const auto moved = [&](index_t v) { return pose.apply(points[v]); };
  std::vector<SurfacePrimitive> ra;
  for (const SurfacePrimitive& s : ia.regions) ra.push_back(transform_surface(s, pose));
  const double tol = 1e-6;
  const auto fa = classify_object_faces(moved, a.faces, ra, tol);
  const auto fb = classify_object_faces([&](index_t v) { return points[v]; }, b.faces, ib.regions, tol);
  for (const index_t r : fa) ASSERT_GE(r, 0);
  for (const index_t r : fb) ASSERT_GE(r, 0);
  const auto contacts = detect_contacts(moved, a, fa, ra, points, b, fb, ib.regions, tol, 2.0);
  ASSERT_EQ(contacts.size(), 1u) << "one pair of faces touches";
  const ContactRegion& c = contacts[0];
  EXPECT_EQ(c.surface.type, SurfaceType::Plane);
  // The moving face's vertices with y in [0.25, 1] (y = i / 8: i = 2..8) on
  // 9 rows; the fixed face's with y in [0.25, 1] (y = 0.25 + 1.5 j / 12:
  // j = 0..6) on 13 rows.
  EXPECT_EQ(c.moving_vertices.size(), 7u * 9u);
  EXPECT_EQ(c.other_vertices.size(), 7u * 13u);
  for (const index_t v : c.moving_vertices) EXPECT_GE(moved(v).y(), 0.25 - tol);
  // Faces of the moving box inside the overlap (centroids): rows 2..7 of
  // squares, area 0.75.
  EXPECT_NEAR(c.moving_area, 0.75, 1e-12);
  EXPECT_EQ(c.other_faces.size(), 2u * 6u * 12u);

  // Apart by 0.01 along x: no contact.
  pose.t = Vec3(2.99, 0, 0);
  ra.clear();
  for (const SurfacePrimitive& s : ia.regions) ra.push_back(transform_surface(s, pose));
  EXPECT_TRUE(detect_contacts(moved, a, fa, ra, points, b, fb, ib.regions, tol, 2.0).empty());
  // Side by side in y, touching only along an edge line (zero area): no
  // faces in contact, the shared line's vertices only.
  pose.t = Vec3(3, 1.75, 0);
  ra.clear();
  for (const SurfacePrimitive& s : ia.regions) ra.push_back(transform_surface(s, pose));
  for (const ContactRegion& e : detect_contacts(moved, a, fa, ra, points, b, fb, ib.regions, tol, 2.0))
    EXPECT_TRUE(e.moving_faces.empty()) << "faces in contact across an edge";
}

}  // namespace
}  // namespace femorph
