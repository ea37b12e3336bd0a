// Thesis 3.4.2, steps 2-3: contact surface regions of the moving object and
// of another object (same surface type and parameters, facing each other),
// and the vertices of each on the overlapping area, found by inclusion tests
// in the 2D chart of the surface (development planes, angles), where mesh
// faces of both objects are compared whatever their discretisation.
#include "adapt/contact.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace femorph {

namespace {

Vec3 face_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double l = n.norm();
  return l > 0 ? Vec3(n / l) : Vec3::Zero();
}

}  // namespace

SurfacePrimitive transform_surface(const SurfacePrimitive& s, const RigidPose& pose) {
  SurfacePrimitive t = s;
  t.point = pose.apply(s.point);
  t.axis = pose.R * s.axis;
  // A cylinder's point is its axis point nearest to the origin.
  if (t.type == SurfaceType::Cylinder) t.point -= t.point.dot(t.axis) * t.axis;
  return t;
}

std::vector<index_t> classify_object_faces(const std::function<Vec3(index_t)>& point, const std::vector<Tri>& faces,
                                           const std::vector<SurfacePrimitive>& regions, double tolerance) {
  std::vector<index_t> out(faces.size(), kInvalidIndex);
  const double cos30 = std::cos(kPi / 6);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Vec3 a = point(faces[f][0]), b = point(faces[f][1]), c = point(faces[f][2]);
    const Vec3 g = (a + b + c) / 3;
    const Vec3 n = face_normal(a, b, c);
    double best = tolerance;
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const SurfacePrimitive& s = regions[r];
      if (s.type == SurfaceType::Unknown) continue;
      const double d = std::max({distance(s, a), distance(s, b), distance(s, c)});
      if (d > best) continue;
      if (std::abs(n.dot(surface_normal(s, g))) < cos30) continue;
      best = d;
      out[f] = static_cast<index_t>(r);
    }
  }
  return out;
}

std::vector<ContactRegion> detect_contacts(const std::function<Vec3(index_t)>& moving_point,
                                           const ObjectBoundary& moving, const std::vector<index_t>& moving_face_region,
                                           const std::vector<SurfacePrimitive>& moving_regions,
                                           const std::vector<Vec3>& points, const ObjectBoundary& other,
                                           const std::vector<index_t>& other_face_region,
                                           const std::vector<SurfacePrimitive>& other_regions, double tolerance,
                                           double scale, double reach) {
  std::vector<ContactRegion> out;
  const auto other_point = [&points](index_t v) { return points[v]; };
  const auto faces_of = [](const std::vector<index_t>& face_region, index_t r) {
    std::vector<index_t> f;
    for (std::size_t i = 0; i < face_region.size(); ++i)
      if (face_region[i] == r) f.push_back(static_cast<index_t>(i));
    return f;
  };
  for (std::size_t a = 0; a < moving_regions.size(); ++a) {
    const SurfacePrimitive& sa = moving_regions[a];
    if (sa.type == SurfaceType::Unknown) continue;
    for (std::size_t b = 0; b < other_regions.size(); ++b) {
      const SurfacePrimitive& sb = other_regions[b];
      if (sb.type != sa.type || !same_surface(sa, sb, tolerance / scale, scale, tolerance / scale)) continue;
      const std::vector<index_t> fa = faces_of(moving_face_region, static_cast<index_t>(a));
      const std::vector<index_t> fb = faces_of(other_face_region, static_cast<index_t>(b));
      if (fa.empty() || fb.empty()) continue;
      // The chart centred on the other region's area-weighted centroid.
      Vec3 centre = Vec3::Zero();
      double area = 0, edge = 0;
      for (const index_t f : fb) {
        const Vec3 p = points[other.faces[f][0]], q = points[other.faces[f][1]], r = points[other.faces[f][2]];
        const double w = 0.5 * (q - p).cross(r - p).norm();
        centre += w * (p + q + r) / 3;
        area += w;
        edge += (q - p).norm() + (r - q).norm() + (p - r).norm();
      }
      if (area <= 0) continue;
      edge /= 3.0 * static_cast<double>(fb.size());
      const SurfaceChart chart = make_surface_chart(sb, closest_point(sb, centre / area));
      ChartTriangles in_b(chart, edge), in_a(chart, edge);
      for (const index_t f : fb) in_b.add(other_point(other.faces[f][0]), other_point(other.faces[f][1]), other_point(other.faces[f][2]));
      for (const index_t f : fa) in_a.add(moving_point(moving.faces[f][0]), moving_point(moving.faces[f][1]), moving_point(moving.faces[f][2]));
      ContactRegion c;
      c.moving_material = moving.material;
      c.other_material = other.material;
      c.moving_region = static_cast<index_t>(a);
      c.other_region = static_cast<index_t>(b);
      c.surface = sb;
      // Facing each other: outward normals opposite (tested on one face
      // pair near the overlap below).
      std::unordered_set<index_t> va, vb;
      for (const index_t f : fa)
        for (const index_t v : moving.faces[f])
          if (!va.count(v) && in_b.contains(chart.map(moving_point(v)), std::max(tolerance, reach))) va.insert(v);
      for (const index_t f : fb)
        for (const index_t v : other.faces[f])
          if (!vb.count(v) && in_a.contains(chart.map(points[v]), std::max(tolerance, reach))) vb.insert(v);
      bool facing = true;
      for (const index_t f : fa) {
        const Vec3 p = moving_point(moving.faces[f][0]), q = moving_point(moving.faces[f][1]),
                   r = moving_point(moving.faces[f][2]);
        const Vec3 g = (p + q + r) / 3;
        if (!in_b.contains(chart.map(g), 0)) continue;
        c.moving_faces.push_back(f);
        c.moving_area += 0.5 * (q - p).cross(r - p).norm();
        // The other's outward normal at g is its surface normal (convex) or
        // its opposite: compare with one of its faces there.
        if (c.moving_faces.size() == 1) {
          double nearest = 3 * edge;
          for (const index_t h : fb) {
            const Vec3 x = points[other.faces[h][0]], y = points[other.faces[h][1]], z = points[other.faces[h][2]];
            const double d = ((x + y + z) / 3 - g).norm();
            if (d >= nearest) continue;
            nearest = d;
            facing = face_normal(p, q, r).dot(face_normal(x, y, z)) < 0;
          }
        }
      }
      if (!facing) continue;
      for (const index_t f : fb) {
        const Vec3 g = (points[other.faces[f][0]] + points[other.faces[f][1]] + points[other.faces[f][2]]) / 3;
        if (in_a.contains(chart.map(g), 0)) c.other_faces.push_back(f);
      }
      if (c.moving_faces.empty() && c.other_faces.empty() && (reach <= 0 || va.empty() || vb.empty())) continue;
      c.moving_vertices.assign(va.begin(), va.end());
      c.other_vertices.assign(vb.begin(), vb.end());
      std::sort(c.moving_vertices.begin(), c.moving_vertices.end());
      std::sort(c.other_vertices.begin(), c.other_vertices.end());
      out.push_back(std::move(c));
    }
  }
  return out;
}

}  // namespace femorph
