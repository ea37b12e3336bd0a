// Analytic surfaces the segmentation recognises (thesis 2.4): plane,
// cylinder, cone, sphere, torus. The type codes are stored in the RegionType
// field array (docs/ARCHITECTURE.md, "Data that flows between filters").
#pragma once

#include "common/types.h"

namespace femorph {

enum class SurfaceType : std::int32_t { Plane = 0, Cylinder = 1, Cone = 2, Sphere = 3, Torus = 4, Unknown = 5 };

/// "plane", "cylinder", "cone", "sphere", "torus", "unknown".
const char* to_string(SurfaceType type);

/// One analytic surface. Conventions:
///   plane     point: a point on it;            axis: unit normal
///   cylinder  point: the axis point closest to the origin; axis: unit direction; radius
///   cone      point: the apex;                 axis: unit direction from the apex into the
///             cone (the nappe used);           half_angle in (0, pi/2), radians
///   sphere    point: the centre;               radius
///   torus     point: the centre;               axis: unit; radius: major R; minor_radius: r
struct SurfacePrimitive {
  SurfaceType type = SurfaceType::Unknown;
  Vec3 point = Vec3::Zero();
  Vec3 axis = Vec3::Zero();
  double radius = 0;
  double minor_radius = 0;
  double half_angle = 0;
};

/// Signed distance from p to the surface: positive on the side its normal
/// (surface_normal) points to: plane along `axis`; cylinder, cone, sphere and
/// torus away from the axis / centre / core circle. For a cone, the distance
/// to its one nappe (points behind the apex measure to the apex, positive).
/// Torus: distance to the core circle minus r, exact for R > r and a finite,
/// continuous bound when R <= r. Unknown: NaN.
double signed_distance(const SurfacePrimitive& s, const Vec3& p);

/// |signed_distance|.
inline double distance(const SurfacePrimitive& s, const Vec3& p) {
  const double d = signed_distance(s, p);
  return d < 0 ? -d : d;
}

/// The point of the surface closest to p (for points on an axis, where it is
/// not unique, any closest point). Unknown: p.
Vec3 closest_point(const SurfacePrimitive& s, const Vec3& p);

/// Unit normal at the point of the surface closest to p, oriented as in
/// signed_distance, so that p = closest_point + signed_distance * normal
/// (behind a cone's apex: the unit direction apex -> p). Unknown: zero.
Vec3 surface_normal(const SurfacePrimitive& s, const Vec3& p);

/// Same surface up to relative tolerance `rel` on lengths (times `scale`, a
/// length of the part, for positions) and `angle` radians on directions and
/// cone half angles; the sign of axes is ignored, except for cones (it picks
/// the nappe). Positions compared: plane offsets, axis lines, apex, centres. Used to count CAD faces of one primitive as one.
bool same_surface(const SurfacePrimitive& a, const SurfacePrimitive& b, double rel, double scale, double angle);

}  // namespace femorph
