// The dimension of Table 2.7 a plan controls, measured on the surfaces.
#include "deform/deform_internal.h"

#include <algorithm>
#include <cmath>

namespace femorph {

namespace {
/// Chamfer ends A (on the reference face) and B for the chamfer surface s.
bool chamfer_ends(const DeformPlan::Feature& f, const SurfacePrimitive& s, double tol, Vec2& a, Vec2& b) {
  ProfileLine lc;
  return profile_line(f.frame, s, lc, 1e-3, tol) && offset_intersection(lc, 0, f.line_r, 0, a) &&
         offset_intersection(lc, 0, f.line_o, 0, b);
}
}  // namespace

double measure_dimension(const DeformPlan& plan, const std::vector<SurfacePrimitive>& surfaces) {
  const index_t control = plan.options.control_region;
  const SurfacePrimitive& c = surfaces[control];
  const DeformPlan::Feature& f = *plan.feature;
  switch (plan.options.type) {
    case DeformationType::Distance:
      return std::abs((c.point - surfaces[plan.reference.front()].point).dot(c.axis));
    case DeformationType::CylinderRadius:
    case DeformationType::SphereRadius:
      return c.radius;
    case DeformationType::FilletRadius:
      return c.type == SurfaceType::Torus ? c.minor_radius : c.radius;
    case DeformationType::ChamferLength:
    case DeformationType::ChamferAngle: {
      Vec2 a, b;
      if (!chamfer_ends(f, c, 1e-4 * plan.part_size, a, b)) return std::numeric_limits<double>::quiet_NaN();
      if (plan.options.type == DeformationType::ChamferLength) return (a - f.edge).norm();
      const Vec2 u = (f.edge - a).normalized(), v = (b - a).normalized();
      return std::acos(std::clamp(u.dot(v), -1.0, 1.0)) * 180 / kPi;
    }
    case DeformationType::Position:
      return 0;  // the distance moved: deform_mesh counts it
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace femorph
