// Boundary curves between surface regions (thesis 2.4.6): straight line,
// circle, circular arc, ellipse, elliptic arc, parabola, hyperbola or
// unclassified, with fitted parameters.
#pragma once

#include "geometry/surface_primitive.h"

#include <vector>

namespace femorph {

enum class CurveType : std::int32_t {
  Line = 0,
  Circle = 1,
  CircularArc = 2,
  Ellipse = 3,
  EllipticArc = 4,
  Parabola = 5,
  Hyperbola = 6,
  Unclassified = 7
};

/// "line", "circle", "circular arc", "ellipse", "elliptic arc", "parabola",
/// "hyperbola", "unclassified".
const char* to_string(CurveType type);

/// Parameters of a curve (thesis 2.5.1.1):
///   line         start, end (the end points), direction (unit)
///   circle       center, normal (of its plane, unit, oriented by the
///                right-hand rule along the points: an arc runs counter-
///                clockwise about it from start to end), radius
///   circular arc center, normal, radius, start, end
///   ellipse / elliptic arc  center, normal, direction (major axis, unit),
///                radius (semi-major), minor_radius (semi-minor); arcs: start, end
///   parabola     normal of the plane; center: the vertex; direction: the axis
///                (unit, from the vertex into the opening); radius: the focal
///                length (vertex to focus); start, end
///   hyperbola    normal of the plane; center: the vertex of the branch the
///                points lie on; direction: the transverse axis (unit, from the
///                hyperbola's centre through that vertex); radius: semi-transverse
///                axis a; minor_radius: semi-conjugate axis b; start, end
///   unclassified start, end
struct CurvePrimitive {
  CurveType type = CurveType::Unclassified;
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  Vec3 direction = Vec3::Zero();
  double radius = 0;
  double minor_radius = 0;
  Vec3 start = Vec3::Zero();
  Vec3 end = Vec3::Zero();
};

struct CurveFit {
  CurvePrimitive curve;
  double max_abs = 0;  // largest distance of the points to the fitted curve (0 when unclassified)
  bool ok = false;     // false: too few points (2 open, 3 closed) or a closed chain on a line
};

/// Classifies an ordered chain of boundary vertices (thesis 2.4.6):
/// `closed` for a loop, else from its first to its last point (two feature
/// vertices). `tolerance`: absolute distance for "lies on". `a`, `b`: the
/// surfaces of the two regions it separates, used to tell which conic a
/// plane section is (step 3 (b)); pass Unknown surfaces when not known.
/// Steps: line (if not closed) -> plane curve? -> circle / arc (fitted),
/// else by the surfaces' intersection type: ellipse (plane x cylinder
/// oblique, or cone section closed), parabola, hyperbola (cone sections by
/// the angle of the plane), else unclassified. Beyond the thesis: a planar
/// curve that fits a circle is a circle / arc whatever the surfaces; when the
/// expected cone section does not fit, the parabola and then the conic's own
/// discriminant (ellipse or hyperbola) are tried before giving up. Circles are
/// least squares (thesis: RANSAC): the chain has no outliers.
CurveFit classify_boundary_curve(const std::vector<Vec3>& points, bool closed, double tolerance,
                                 const SurfacePrimitive& a, const SurfacePrimitive& b);

}  // namespace femorph
