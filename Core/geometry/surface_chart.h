// 2D charts of the analytic surfaces (thesis 3.4.2, step 3): the spaces in
// which Adapt tests whether a vertex lies in the overlap of two contacting
// surface regions, and in which it re-triangulates contact regions (3.5.4).
#pragma once

#include "geometry/surface_primitive.h"
#include "geometry/triangulate_2d.h"

#include <unordered_map>

namespace femorph {

/// A chart centred on a point of the surface (angles are measured from the
/// centre's, in (-pi, pi]: the seam lies opposite the centre). Coordinates,
/// all lengths:
///   plane     in-plane coordinates about the centre's projection;
///   cylinder  (r theta, height): the development plane;
///   cone      the development plane, the apex at the origin, the centre's
///             generator along +u;
///   sphere    (r longitude, r latitude) about the great circle through the
///             centre (the poles 90 degrees away from it);
///   torus     (R toroidal angle, r poloidal angle).
/// `period` is the coordinate shift of one turn around the seam where the
/// chart has one (cylinder, sphere: u; torus: u and v; else 0). Regions that
/// cross the seam must unwrap across it (unwrap()).
struct SurfaceChart {
  SurfacePrimitive surface;
  Vec3 origin = Vec3::Zero();  ///< plane: the centre's projection
  Vec3 e1 = Vec3::Zero(), e2 = Vec3::Zero(), e3 = Vec3::Zero();  ///< right-handed frame
  double poloidal0 = 0;        ///< torus: the centre's poloidal angle
  Vec2 period = Vec2::Zero();

  /// Chart coordinates of the surface point nearest to p.
  Vec2 map(const Vec3& p) const;
  /// The surface point with chart coordinates q.
  Vec3 lift(const Vec2& q) const;
  /// q shifted by whole periods to lie within half a period of `near`.
  Vec2 unwrap(const Vec2& q, const Vec2& near) const;
};

/// The chart of s centred on `centre` (a point on or near s; for a cone not
/// its apex). Unknown surfaces: a plane chart is meaningless, so callers must
/// not ask (the result maps everything to the origin).
SurfaceChart make_surface_chart(const SurfacePrimitive& s, const Vec3& centre);

/// Triangles in a chart (each unwrapped across the seam from its first
/// vertex), binned on a grid of `cell`, for inclusion tests (thesis 3.4.2
/// step 3).
class ChartTriangles {
 public:
  ChartTriangles(const SurfaceChart& chart, double cell) : chart_(chart), cell_(cell > 0 ? cell : 1) {}
  /// Adds the triangle with these 3D corners; returns its index.
  index_t add(const Vec3& a, const Vec3& b, const Vec3& c);
  /// Adds a triangle given in chart coordinates (already unwrapped).
  index_t add(const std::array<Vec2, 3>& t);
  /// Whether q (or q shifted by a period) lies within `tol` of a triangle.
  bool contains(const Vec2& q, double tol) const;
  const std::array<Vec2, 3>& triangle(index_t t) const { return tris_[t]; }
  index_t size() const { return static_cast<index_t>(tris_.size()); }

 private:
  long cell_of(double x) const;
  const SurfaceChart& chart_;
  double cell_;
  std::vector<std::array<Vec2, 3>> tris_;
  std::unordered_map<std::uint64_t, std::vector<index_t>> bins_;
};

/// Distance in the plane from q to the triangle (a, b, c) (0 inside).
double distance_to_triangle_2d(const Vec2& q, const Vec2& a, const Vec2& b, const Vec2& c);

}  // namespace femorph
