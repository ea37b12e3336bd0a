// Table 2.7, third column: the surfaces of the control and following
// regions for a new value of the dimension, and the map that carries a
// point of each onto its updated surface at the same place on the feature
// (Method 1 of thesis 2.5.4.1).
#include "deform/deform_internal.h"

#include <cmath>
#include <sstream>

namespace femorph {

namespace {

using Feature = DeformPlan::Feature;

SurfaceUpdate failed(std::string why) {
  SurfaceUpdate u;
  u.error = std::move(why);
  return u;
}

/// A rigid translation of every moved region (Distance, Position).
SurfaceUpdate translate(const DeformPlan& plan, const DeformRegions& regions, const Vec3& shift) {
  SurfaceUpdate u;
  u.surfaces = regions.surfaces;
  for (const index_t r : plan.moved) u.surfaces[r].point += shift;
  u.map = [shift](index_t, const Vec3& p) { return Vec3(p + shift); };
  return u;
}

/// CylinderRadius: every moved region shifts away from the axis by delta
/// (the cylinder's radius, coaxial tori's major radius, cones' apex).
SurfaceUpdate radial_shift(const DeformPlan& plan, const DeformRegions& regions, double value) {
  const ProfileFrame frame = plan.feature->frame;
  const double delta = value - plan.current;
  if (!(value > 0)) return failed("a cylinder radius must be positive");
  SurfaceUpdate u;
  u.surfaces = regions.surfaces;
  for (const index_t r : plan.moved) {
    SurfacePrimitive& s = u.surfaces[r];
    switch (s.type) {
      case SurfaceType::Cylinder:
        s.radius += delta;
        if (!(s.radius > 0)) return failed("a following cylinder's radius would vanish");
        break;
      case SurfaceType::Torus:
        s.radius += delta;
        if (!(s.radius > 0)) return failed("a following torus would lose its hole");
        break;
      case SurfaceType::Cone:
        s.point -= (delta / std::tan(s.half_angle)) * s.axis;
        break;
      default:
        break;
    }
  }
  u.map = [frame, delta](index_t, const Vec3& p) {
    const Vec2 q = frame.to2d(p);
    return frame.from2d(Vec2(q.x() + delta, q.y()), p);
  };
  return u;
}

/// SphereRadius: about the centre, kept.
SurfaceUpdate scale_sphere(const DeformPlan& plan, const DeformRegions& regions, double value) {
  if (!(value > 0)) return failed("a sphere radius must be positive");
  SurfaceUpdate u;
  u.surfaces = regions.surfaces;
  const index_t control = plan.options.control_region;
  const Vec3 centre = regions.surfaces[control].point;
  const double k = value / regions.surfaces[control].radius;
  u.surfaces[control].radius = value;
  u.map = [centre, k](index_t, const Vec3& p) { return Vec3(centre + k * (p - centre)); };
  return u;
}

/// FilletRadius: each fillet's profile circle rebuilt tangent to its two
/// lines with the new radius; its points keep their angle on the circle.
SurfaceUpdate rebuild_fillets(const DeformPlan& plan, const DeformRegions& regions, double value) {
  if (!(value > 0)) return failed("a fillet radius must be positive");
  const Feature& f = *plan.feature;
  SurfaceUpdate u;
  u.surfaces = regions.surfaces;
  struct Rebuilt {
    Feature::Fillet fillet;
    Vec2 center;
    double t_lo, t_hi;
  };
  auto rebuilt = std::make_shared<std::vector<Rebuilt>>();
  std::vector<index_t> fillet_of(regions.size(), -1);
  for (const Feature::Fillet& fl : f.fillets) {
    Vec2 q;
    if (!offset_intersection(fl.a, fl.sa * value, fl.b, fl.sb * value, q)) return failed("a fillet's faces are parallel");
    SurfacePrimitive& s = u.surfaces[fl.region];
    if (fl.frame.axisymmetric) {
      if (!(q.x() > 0)) return failed("a toroidal fillet would reach its axis");
      s.point = fl.frame.origin + q.y() * fl.frame.axis;
      s.radius = q.x();
      s.minor_radius = value;
    } else {
      s.point = fl.frame.from2d(q, fl.frame.origin);
      s.radius = value;
    }
    fillet_of[fl.region] = static_cast<index_t>(rebuilt->size());
    rebuilt->push_back({fl, q, fl.t_lo, fl.t_hi});
  }
  // Sphere corners at the point nearest to their fillets' new axes.
  std::vector<Vec3> corner_center(regions.size(), Vec3::Zero());
  for (const Feature::Corner& c : f.corners) {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    Vec3 rhs = Vec3::Zero();
    for (const int i : c.fillets) {
      const Vec3& d = (*rebuilt)[i].fillet.frame.axis;
      const Vec3 p = u.surfaces[(*rebuilt)[i].fillet.region].point;
      const Eigen::Matrix3d proj = Eigen::Matrix3d::Identity() - d * d.transpose();
      m += proj;
      rhs += proj * p;
    }
    const Vec3 centre = m.ldlt().solve(rhs);
    u.surfaces[c.region].point = centre;
    u.surfaces[c.region].radius = value;
    corner_center[c.region] = centre;
  }
  // Prismatic fillets ending at a corner: their axial range follows it.
  for (Rebuilt& r : *rebuilt) {
    const Feature::Fillet& fl = r.fillet;
    if (fl.frame.axisymmetric) continue;
    if (fl.sphere_lo >= 0) r.t_lo = (corner_center[fl.sphere_lo] - fl.frame.origin).dot(fl.frame.axis);
    if (fl.sphere_hi >= 0) r.t_hi = (corner_center[fl.sphere_hi] - fl.frame.origin).dot(fl.frame.axis);
  }
  auto spheres = std::make_shared<std::vector<std::pair<Vec3, Vec3>>>(regions.size());  // old, new centre
  for (const Feature::Corner& c : f.corners) (*spheres)[c.region] = {regions.surfaces[c.region].point, corner_center[c.region]};
  const double old_radius = plan.current;
  u.map = [rebuilt, fillet_of, spheres, value, old_radius](index_t region, const Vec3& p) -> Vec3 {
    const double k = value / old_radius;
    const index_t i = region >= 0 && region < static_cast<index_t>(fillet_of.size()) ? fillet_of[region] : -1;
    if (i < 0) {  // a sphere corner
      const auto& c = (*spheres)[region];
      return c.second + k * (p - c.first);
    }
    const Rebuilt& r = (*rebuilt)[i];
    const ProfileFrame& frame = r.fillet.frame;
    const Vec2 q = frame.to2d(p);
    Vec3 out = frame.from2d(r.center + k * (q - r.fillet.center), p);
    if (!frame.axisymmetric && r.fillet.t_hi > r.fillet.t_lo) {
      const double t = (p - frame.origin).dot(frame.axis);
      const double s = (t - r.fillet.t_lo) / (r.fillet.t_hi - r.fillet.t_lo);
      const double t_new = r.t_lo + s * (r.t_hi - r.t_lo);
      out += (t_new - t) * frame.axis;
    }
    return out;
  };
  return u;
}

/// Chamfers: the chamfer's ends A' (on the reference face) and B' for the
/// new length or angle; its points keep their place along A'B'.
SurfaceUpdate rebuild_chamfer(const DeformPlan& plan, const DeformRegions& regions, double value) {
  const Feature& f = *plan.feature;
  const Vec2 e = f.edge;
  Vec2 a = f.end_a, b = f.end_b;
  // Current ends on the surfaces as measured (the plan's).
  const double la = (a - e).norm(), lb = (b - e).norm();
  double la2 = la, lb2 = lb;
  if (plan.options.type == DeformationType::ChamferLength) {
    if (!(value > 0)) return failed("a chamfer length must be positive");
    la2 = value;
    lb2 = lb * value / la;
  } else {
    const double theta = value * kPi / 180;
    const double opposite = kPi - theta - f.gamma;
    if (!(theta > 0) || !(opposite > 1e-6)) {
      std::ostringstream os;
      os << "a chamfer angle must lie between 0 and " << (kPi - f.gamma) * 180 / kPi
         << " degrees (the faces meet at " << f.gamma * 180 / kPi << " degrees)";
      return failed(os.str());
    }
    lb2 = la * std::sin(theta) / std::sin(opposite);
  }
  const Vec2 a2 = e + (a - e) * (la2 / la), b2 = e + (b - e) * (lb2 / lb);
  SurfaceUpdate u;
  u.surfaces = regions.surfaces;
  const index_t control = plan.options.control_region;
  SurfacePrimitive& s = u.surfaces[control];
  const ProfileFrame frame = f.frame;
  Vec2 dir = (b2 - a2).normalized();
  if (frame.axisymmetric) {
    if (dir.x() < 0) dir = -dir;  // from the apex into the cone
    if (std::abs(dir.x()) < 1e-9 || std::abs(dir.y()) < 1e-9) return failed("the chamfer cone would become flat or a cylinder");
    const double t = -a2.x() / (b2.x() - a2.x());
    const double z_apex = a2.y() + t * (b2.y() - a2.y());
    s.point = frame.origin + z_apex * frame.axis;
    s.axis = (dir.y() > 0 ? 1.0 : -1.0) * frame.axis;
    s.half_angle = std::atan2(std::abs(dir.x()), std::abs(dir.y()));
  } else {
    const Vec2 n2(-dir.y(), dir.x());
    Vec3 n = n2.x() * frame.e1 + n2.y() * frame.e2;
    if (n.dot(regions.surfaces[control].axis) < 0) n = -n;
    s.axis = n.normalized();
    s.point = frame.from2d(a2, frame.origin);
  }
  const Vec2 ab = b - a, ab2 = b2 - a2;
  const Vec2 normal(-ab.y(), ab.x()), normal2(-ab2.y(), ab2.x());
  u.map = [frame, a, ab, a2, ab2, normal, normal2](index_t, const Vec3& p) {
    const Vec2 q = frame.to2d(p);
    const double lambda = (q - a).dot(ab) / ab.squaredNorm();
    const double mu = (q - a).dot(normal) / normal.squaredNorm();
    return frame.from2d(a2 + lambda * ab2 + mu * normal2, p);
  };
  return u;
}

}  // namespace

SurfaceUpdate update_region_surfaces(const DeformPlan& plan, const DeformRegions& regions, double value) {
  if (!std::isfinite(value)) return failed("the target value is not a number");
  switch (plan.options.type) {
    case DeformationType::Distance:
      if (!(value > 0)) return failed("a distance must be positive");
      return translate(plan, regions, (value - plan.current) * plan.feature->direction);
    case DeformationType::Position:
      return translate(plan, regions, (value - plan.current) * plan.feature->direction);
    case DeformationType::CylinderRadius:
      return radial_shift(plan, regions, value);
    case DeformationType::SphereRadius:
      return scale_sphere(plan, regions, value);
    case DeformationType::FilletRadius:
      return rebuild_fillets(plan, regions, value);
    case DeformationType::ChamferAngle:
    case DeformationType::ChamferLength:
      return rebuild_chamfer(plan, regions, value);
  }
  return failed("unknown deformation type");
}

}  // namespace femorph
