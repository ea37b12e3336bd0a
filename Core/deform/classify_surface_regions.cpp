// Surface region classification (thesis 2.5.2, Figs. 2.20-2.21): control,
// following, deformed and fixed regions, the reference of the dimension,
// and the feature geometry the update of Table 2.7 works in.
#include "deform/deform_internal.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace femorph {

const char* to_string(DeformationType type) {
  switch (type) {
    case DeformationType::Distance: return "Distance";
    case DeformationType::CylinderRadius: return "CylinderRadius";
    case DeformationType::FilletRadius: return "FilletRadius";
    case DeformationType::ChamferAngle: return "ChamferAngle";
    case DeformationType::ChamferLength: return "ChamferLength";
    case DeformationType::SphereRadius: return "SphereRadius";
    case DeformationType::Position: return "Position";
  }
  return "unknown";
}

const char* to_string(RegionRole role) {
  switch (role) {
    case RegionRole::Fixed: return "fixed";
    case RegionRole::Control: return "control";
    case RegionRole::Following: return "following";
    case RegionRole::Deformed: return "deformed";
  }
  return "unknown";
}

namespace {

using Feature = DeformPlan::Feature;

std::string region_name(const DeformRegions& regions, index_t r) {
  std::ostringstream os;
  os << "region " << r << " (" << to_string(regions.surfaces[r].type) << ")";
  return os.str();
}

/// Inclined to the control region like a chamfer: its faces meet the
/// control region's at 20 to 70 degrees (a cone next to a plane normal to
/// its axis: 90 degrees minus its half angle; next to a coaxial cylinder:
/// its half angle). A steeper or flatter face is a taper or a step, and
/// deforms instead.
bool inclined(const DeformRegions& regions, index_t control, index_t r) {
  const SurfacePrimitive& s = regions.surfaces[r];
  const SurfacePrimitive& c = regions.surfaces[control];
  double deg = -1;
  if (s.type == SurfaceType::Cone) {
    const double half = s.half_angle * 180 / kPi;
    if (c.type == SurfaceType::Plane) deg = 90 - half;
    else if (c.type == SurfaceType::Cylinder) deg = half;
    else deg = 45;
  } else if (s.type == SurfaceType::Plane) {
    if (c.type == SurfaceType::Plane) deg = std::acos(std::min(1.0, std::abs(s.axis.dot(c.axis)))) * 180 / kPi;
    else if (c.type == SurfaceType::Cylinder || c.type == SurfaceType::Cone)
      deg = std::asin(std::min(1.0, std::abs(s.axis.dot(c.axis)))) * 180 / kPi;
  }
  return deg >= 20 && deg <= 70;
}

double fillet_radius(const SurfacePrimitive& s) {
  return s.type == SurfaceType::Torus ? s.minor_radius : s.radius;
}

/// 2.5.2 for types (1)-(6): the fillets (G1 cylinders and tori) and
/// chamfers (small inclined planes and cones) of the control region, and the
/// equal-radius sphere corners of those fillets.
std::vector<index_t> automatic_following(const DeformRegions& regions, const RegionGraph& graph,
                                         const DeformOptions& options) {
  const index_t control = options.control_region;
  std::set<index_t> following;
  std::vector<index_t> fillets;
  const auto& types = regions.surfaces;
  if (options.type == DeformationType::FilletRadius) {
    // The control is the fillet: its equal-radius corners and the fillets
    // meeting there, transitively.
    const double r = fillet_radius(types[control]);
    std::vector<index_t> stack{control};
    std::set<index_t> seen{control};
    while (!stack.empty()) {
      const index_t f = stack.back();
      stack.pop_back();
      for (const index_t n : graph.neighbors[f]) {
        if (seen.count(n) || !graph.tangent(f, n)) continue;
        const SurfaceType t = types[n].type;
        const bool sphere = t == SurfaceType::Sphere && types[f].type != SurfaceType::Sphere;
        const bool fillet = types[f].type == SurfaceType::Sphere &&
                            (t == SurfaceType::Cylinder || t == SurfaceType::Torus);
        if ((sphere || fillet) && std::abs(fillet_radius(types[n]) - r) <= options.radius_tolerance * r) {
          seen.insert(n);
          following.insert(n);
          stack.push_back(n);
        }
      }
    }
    return {following.begin(), following.end()};
  }
  if (options.type == DeformationType::ChamferAngle || options.type == DeformationType::ChamferLength ||
      options.type == DeformationType::SphereRadius) {
    return {};
  }
  for (const index_t n : graph.neighbors[control]) {
    const SurfaceType t = types[n].type;
    if ((t == SurfaceType::Cylinder || t == SurfaceType::Torus) && graph.tangent(control, n)) {
      following.insert(n);
      fillets.push_back(n);
    } else if ((t == SurfaceType::Plane || t == SurfaceType::Cone) && !graph.tangent(control, n) &&
               graph.area[n] < options.chamfer_area_ratio * graph.area[control] && inclined(regions, control, n)) {
      following.insert(n);
    }
  }
  for (const index_t f : fillets) {
    for (const index_t n : graph.neighbors[f]) {
      if (types[n].type == SurfaceType::Sphere && graph.tangent(f, n) &&
          std::abs(types[n].radius - fillet_radius(types[f])) <= options.radius_tolerance * fillet_radius(types[f])) {
        following.insert(n);
      }
    }
  }
  following.erase(control);
  return {following.begin(), following.end()};
}

/// Distance: the nearest plane parallel to the control plane.
Status distance_reference(const DeformRegions& regions, const DeformPlan& plan, index_t& reference) {
  const index_t control = plan.options.control_region;
  const SurfacePrimitive& c = regions.surfaces[control];
  const double tol = 1e-9 * plan.part_size;
  if (!plan.options.reference_regions.empty()) {
    reference = plan.options.reference_regions.front();
    const SurfacePrimitive& r = regions.surfaces[reference];
    if (r.type != SurfaceType::Plane || r.axis.cross(c.axis).norm() > 1e-3) {
      return Status::failure("ReferenceRegions: " + region_name(regions, reference) +
                             " is no plane parallel to the control plane, region " + std::to_string(control) +
                             "; Distance is measured between two parallel planes.");
    }
    if (std::abs((c.point - r.point).dot(c.axis)) <= tol) {
      return Status::failure("ReferenceRegions: region " + std::to_string(reference) +
                             " lies in the control plane; choose the opposite plane.");
    }
    return Status::success();
  }
  double best = std::numeric_limits<double>::infinity();
  reference = kInvalidIndex;
  for (index_t r = 0; r < static_cast<index_t>(regions.size()); ++r) {
    const SurfacePrimitive& s = regions.surfaces[r];
    if (r == control || s.type != SurfaceType::Plane || s.axis.cross(c.axis).norm() > 1e-3) continue;
    const double d = std::abs((c.point - s.point).dot(c.axis));
    if (d > tol && d < best) {
      best = d;
      reference = r;
    }
  }
  if (reference < 0) {
    return Status::failure("no plane is parallel to the control plane, region " + std::to_string(control) +
                           "; Distance needs two parallel planes.");
  }
  return Status::success();
}

/// Roles for Position (Fig. 2.21): the reference planes are deformed, G1
/// cylinders joining two of them too, and the object is every region
/// reachable from the control region without crossing them.
Status position_roles(const DeformRegions& regions, const RegionGraph& graph, DeformPlan& plan) {
  const DeformOptions& o = plan.options;
  const index_t control = o.control_region;
  const double length = o.translation.norm();
  if (!(length > 0)) {
    return Status::failure("Position needs a nonzero Translation.");
  }
  const Vec3 dir = o.translation / length;
  std::vector<index_t> reference = o.reference_regions;
  if (reference.empty()) {
    // Planes parallel to the translation within two region steps of the
    // control region, larger than twice it.
    std::set<index_t> near{control};
    for (int step = 0; step < 2; ++step) {
      std::set<index_t> next = near;
      for (const index_t r : near) next.insert(graph.neighbors[r].begin(), graph.neighbors[r].end());
      near = next;
    }
    for (const index_t r : near) {
      const SurfacePrimitive& s = regions.surfaces[r];
      if (r != control && s.type == SurfaceType::Plane && std::abs(s.axis.dot(dir)) < 1e-6 &&
          graph.area[r] > 2 * graph.area[control]) {
        reference.push_back(r);
      }
    }
    if (reference.empty()) {
      return Status::failure("Position: no plane parallel to the Translation surrounds the object of region " +
                             std::to_string(control) + "; give the plane(s) it sits on in ReferenceRegions.");
    }
  }
  for (const index_t r : reference) {
    const SurfacePrimitive& s = regions.surfaces[r];
    if (s.type != SurfaceType::Plane) {
      return Status::failure("ReferenceRegions: " + region_name(regions, r) +
                             " is no plane; Position moves an object on planes.");
    }
    if (std::abs(s.axis.dot(dir)) > 1e-6) {
      std::ostringstream os;
      os << "the Translation (" << o.translation.x() << ", " << o.translation.y() << ", " << o.translation.z()
         << ") is not parallel to reference plane " << r << " (normal " << s.axis.x() << ", " << s.axis.y() << ", "
         << s.axis.z() << "): Position moves the object in its plane.";
      return Status::failure(os.str());
    }
    if (r == control) return Status::failure("ReferenceRegions must not contain the ControlRegion.");
  }
  std::vector<RegionRole>& roles = plan.roles;
  for (const index_t r : reference) roles[r] = RegionRole::Deformed;
  if (reference.size() == 2) {
    for (const index_t n : graph.neighbors[reference[0]]) {
      if (regions.surfaces[n].type == SurfaceType::Cylinder && graph.tangent(reference[0], n) &&
          graph.tangent(reference[1], n)) {
        roles[n] = RegionRole::Deformed;
      }
    }
  }
  std::vector<index_t> stack{control};
  roles[control] = RegionRole::Control;
  while (!stack.empty()) {
    const index_t r = stack.back();
    stack.pop_back();
    for (const index_t n : graph.neighbors[r]) {
      if (roles[n] != RegionRole::Fixed) continue;
      roles[n] = RegionRole::Control;
      stack.push_back(n);
    }
  }
  std::size_t object = 0;
  for (const RegionRole role : roles) object += role == RegionRole::Control;
  if (object + reference.size() >= regions.size()) {
    return Status::failure("Position: the reference plane(s) do not separate the object of region " +
                           std::to_string(control) +
                           " from the rest of the part (every region is reachable from it); give the plane(s) "
                           "it sits on in ReferenceRegions.");
  }
  plan.reference = reference;
  plan.feature = std::make_shared<Feature>([&] {
    Feature f;
    f.direction = dir;
    return f;
  }());
  return Status::success();
}

/// FilletRadius: every moved fillet with the two lines of its profile it is
/// tangent to, and the sphere corners.
Status fillet_feature(const TetMesh& mesh, const DeformRegions& regions, const RegionGraph& graph, DeformPlan& plan,
                      Feature& feature) {
  const double tol = 1e-4 * plan.part_size;
  for (const index_t r : plan.moved) {
    const SurfacePrimitive& s = regions.surfaces[r];
    if (s.type == SurfaceType::Sphere) continue;
    Feature::Fillet f;
    f.region = r;
    if (s.type == SurfaceType::Cylinder) {
      f.frame = ProfileFrame::prismatic(s.point, s.axis);
      f.center = Vec2::Zero();
      f.radius = s.radius;
    } else if (s.type == SurfaceType::Torus) {
      f.frame.axisymmetric = true;
      f.frame.origin = s.point;
      f.frame.axis = s.axis;
      f.center = Vec2(s.radius, 0);
      f.radius = s.minor_radius;
    } else {
      return Status::failure("FilletRadius: " + region_name(regions, r) + " is no cylinder or torus fillet.");
    }
    std::vector<std::pair<ProfileLine, index_t>> lines;
    for (const index_t n : graph.neighbors[r]) {
      if (plan.roles[n] != RegionRole::Deformed || !graph.tangent(r, n)) continue;
      ProfileLine line;
      if (profile_line(f.frame, regions.surfaces[n], line, 1e-3, tol) &&
          std::abs(std::abs(line.distance(f.center)) - f.radius) <= 0.02 * f.radius) {
        lines.emplace_back(line, n);
      }
    }
    if (lines.size() < 2) {
      return Status::failure("FilletRadius: " + region_name(regions, r) +
                             " is not tangent to two planes, cylinders or cones it can be rebuilt from (found " +
                             std::to_string(lines.size()) +
                             "); fillets between other faces (free-form, spheres, tori) are not supported.");
    }
    f.a = lines[0].first;
    f.b = lines[1].first;
    f.sa = f.a.distance(f.center) > 0 ? 1.0 : -1.0;
    f.sb = f.b.distance(f.center) > 0 ? 1.0 : -1.0;
    feature.fillets.push_back(f);
  }
  // Sphere corners: the prismatic fillets that meet at each.
  for (const index_t r : plan.moved) {
    const SurfacePrimitive& s = regions.surfaces[r];
    if (s.type != SurfaceType::Sphere) continue;
    Feature::Corner corner;
    corner.region = r;
    for (std::size_t i = 0; i < feature.fillets.size(); ++i) {
      const Feature::Fillet& f = feature.fillets[i];
      if (!f.frame.axisymmetric && graph.adjacent(r, f.region)) corner.fillets.push_back(static_cast<int>(i));
    }
    if (corner.fillets.size() < 2) {
      return Status::failure("FilletRadius: sphere corner " + region_name(regions, r) +
                             " does not join two cylindrical fillets; only such corners are supported.");
    }
    feature.corners.push_back(corner);
  }
  // Axial extent of each prismatic fillet and the corners at its ends.
  for (Feature::Fillet& f : feature.fillets) {
    if (f.frame.axisymmetric) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (index_t t = 0; t < mesh.tet_slots(); ++t) {
      if (!mesh.tet_alive(t)) continue;
      for (int k = 0; k < 4; ++k) {
        if (!mesh.is_boundary_face(t, k) || mesh.face_region(t, k) != f.region) continue;
        for (int j = 0; j < 3; ++j) {
          const double a = (mesh.point(mesh.tet(t)[kTetFace[k][j]]) - f.frame.origin).dot(f.frame.axis);
          lo = std::min(lo, a);
          hi = std::max(hi, a);
        }
      }
    }
    f.t_lo = lo;
    f.t_hi = hi;
    for (const Feature::Corner& c : feature.corners) {
      if (!graph.adjacent(c.region, f.region)) continue;
      const double a = (regions.surfaces[c.region].point - f.frame.origin).dot(f.frame.axis);
      (std::abs(a - lo) < std::abs(a - hi) ? f.sphere_lo : f.sphere_hi) = c.region;
    }
  }
  return Status::success();
}

/// Chamfers: the profile of the chamfer between its reference face R and
/// the other face O.
Status chamfer_feature(const DeformRegions& regions, const RegionGraph& graph, DeformPlan& plan, Feature& feature) {
  const index_t control = plan.options.control_region;
  const SurfacePrimitive& c = regions.surfaces[control];
  const double tol = 1e-4 * plan.part_size;
  index_t ref = kInvalidIndex;
  if (!plan.options.reference_regions.empty()) {
    ref = plan.options.reference_regions.front();
    if (!graph.adjacent(control, ref)) {
      return Status::failure("ReferenceRegions: region " + std::to_string(ref) + " is not next to the chamfer, region " +
                             std::to_string(control) + ".");
    }
  } else {
    for (const index_t n : graph.neighbors[control]) {
      if (regions.surfaces[n].type == SurfaceType::Plane && (ref < 0 || graph.area[n] > graph.area[ref])) ref = n;
    }
    if (ref < 0) {
      return Status::failure("the chamfer, region " + std::to_string(control) +
                             ", has no planar neighbour to measure from; give ReferenceRegions.");
    }
  }
  const SurfacePrimitive& rs = regions.surfaces[ref];
  if (c.type == SurfaceType::Cone) {
    feature.frame.axisymmetric = true;
    feature.frame.origin = c.point;
    feature.frame.axis = c.axis;
  } else {
    if (rs.type != SurfaceType::Plane) {
      return Status::failure("ReferenceRegions: a planar chamfer is measured from a plane; " +
                             region_name(regions, ref) + " is none.");
    }
    const Vec3 d = c.axis.cross(rs.axis);
    if (d.norm() < 1e-3) return Status::failure("the chamfer plane is parallel to its reference plane.");
    feature.frame = ProfileFrame::prismatic(c.point, d.normalized());
  }
  ProfileLine lc;
  if (!profile_line(feature.frame, c, lc, 1e-3, tol) || !profile_line(feature.frame, rs, feature.line_r, 1e-3, tol)) {
    return Status::failure("the chamfer, region " + std::to_string(control) + ", and its reference " +
                           region_name(regions, ref) +
                           " do not form a prismatic or axisymmetric profile (the reference must be a plane normal "
                           "to the cone's axis, or a plane meeting the chamfer plane along a line).");
  }
  index_t other = kInvalidIndex;
  for (const index_t n : graph.neighbors[control]) {
    ProfileLine line;
    if (n == ref || !profile_line(feature.frame, regions.surfaces[n], line, 1e-3, tol)) continue;
    if (std::abs(line.n.x() * feature.line_r.n.y() - line.n.y() * feature.line_r.n.x()) < 1e-3) continue;
    if (other < 0 || graph.area[n] > graph.area[other]) {
      other = n;
      feature.line_o = line;
    }
  }
  if (other < 0) {
    return Status::failure("the chamfer, region " + std::to_string(control) +
                           ", has no second face (plane, coaxial cylinder or cone) besides its reference, region " +
                           std::to_string(ref) + ".");
  }
  feature.other_region = other;
  Vec2 e, a, b;
  if (!offset_intersection(feature.line_r, 0, feature.line_o, 0, e) || !offset_intersection(lc, 0, feature.line_r, 0, a) ||
      !offset_intersection(lc, 0, feature.line_o, 0, b)) {
    return Status::failure("the chamfer's faces are parallel in its profile.");
  }
  feature.edge = e;
  feature.end_a = a;
  feature.end_b = b;
  const Vec2 ea = a - e, eb = b - e;
  feature.gamma = std::acos(std::clamp(ea.normalized().dot(eb.normalized()), -1.0, 1.0));
  plan.reference = {ref};
  return Status::success();
}

}  // namespace

Status classify_surface_regions(const TetMesh& mesh, const DeformRegions& regions, const RegionGraph& graph,
                                const DeformOptions& options, DeformPlan& plan) {
  plan = DeformPlan();
  plan.options = options;
  const index_t n = static_cast<index_t>(regions.size());
  const index_t control = options.control_region;
  {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
      if (!mesh.vertex_alive(v)) continue;
      lo = lo.cwiseMin(mesh.point(v));
      hi = hi.cwiseMax(mesh.point(v));
    }
    plan.part_size = (hi - lo).norm();
  }
  if (control < 0 || control >= n) {
    return Status::failure("ControlRegion " + std::to_string(control) + " names no region (the mesh has " +
                           std::to_string(n) + " regions, 0 to " + std::to_string(n - 1) + ").");
  }
  for (const index_t r : options.reference_regions) {
    if (r < 0 || r >= n) return Status::failure("ReferenceRegions: " + std::to_string(r) + " names no region.");
  }
  for (const index_t r : options.following_regions) {
    if (r < 0 || r >= n) return Status::failure("FollowingRegions: " + std::to_string(r) + " names no region.");
  }
  const SurfaceType type = regions.surfaces[control].type;
  const auto need = [&](const char* what) {
    return Status::failure("ControlRegion " + std::to_string(control) + " is a " + to_string(type) +
                           "; DeformationType " + to_string(options.type) + " needs " + what + ".");
  };
  switch (options.type) {
    case DeformationType::Distance:
      if (type != SurfaceType::Plane) return need("a plane");
      break;
    case DeformationType::CylinderRadius:
      if (type != SurfaceType::Cylinder) return need("a cylinder");
      break;
    case DeformationType::FilletRadius:
      if (type != SurfaceType::Cylinder && type != SurfaceType::Torus) return need("a cylindrical or toroidal fillet");
      break;
    case DeformationType::ChamferAngle:
    case DeformationType::ChamferLength:
      if (type != SurfaceType::Plane && type != SurfaceType::Cone) return need("a planar or conical chamfer");
      break;
    case DeformationType::SphereRadius:
      if (type != SurfaceType::Sphere) return need("a sphere");
      break;
    case DeformationType::Position:
      if (type == SurfaceType::Unknown) return need("a fitted surface");
      break;
  }
  plan.roles.assign(n, RegionRole::Fixed);
  if (options.type == DeformationType::Position) {
    const Status s = position_roles(regions, graph, plan);
    if (!s) return s;
  } else {
    plan.roles[control] = RegionRole::Control;
    const std::vector<index_t> following =
        options.override_following ? options.following_regions : automatic_following(regions, graph, options);
    for (const index_t r : following) {
      if (r != control) plan.roles[r] = RegionRole::Following;
    }
    for (index_t r = 0; r < n; ++r) {
      if (plan.roles[r] != RegionRole::Control && plan.roles[r] != RegionRole::Following) continue;
      for (const index_t m : graph.neighbors[r]) {
        if (plan.roles[m] == RegionRole::Fixed) plan.roles[m] = RegionRole::Deformed;
      }
    }
  }
  for (index_t r = 0; r < n; ++r) {
    if (plan.roles[r] == RegionRole::Control || plan.roles[r] == RegionRole::Following) plan.moved.push_back(r);
  }
  for (const index_t r : plan.moved) {
    if (regions.surfaces[r].type == SurfaceType::Unknown) {
      return Status::failure("region " + std::to_string(r) + " would move with the " +
                             (r == control ? std::string("control region") : std::string("control region ") + std::to_string(control)) +
                             " but has no fitted surface; give FollowingRegions without it or segment the mesh "
                             "with other settings.");
    }
  }

  auto feature = std::make_shared<Feature>();
  const SurfacePrimitive& c = regions.surfaces[control];
  const double tol = 1e-4 * plan.part_size;
  switch (options.type) {
    case DeformationType::Distance: {
      index_t ref = kInvalidIndex;
      const Status s = distance_reference(regions, plan, ref);
      if (!s) return s;
      plan.reference = {ref};
      const double side = (c.point - regions.surfaces[ref].point).dot(c.axis);
      feature->direction = side > 0 ? c.axis : Vec3(-c.axis);
      if (plan.roles[ref] != RegionRole::Fixed && plan.roles[ref] != RegionRole::Deformed) {
        return Status::failure("the reference plane, region " + std::to_string(ref) +
                               ", would move with the control region; choose another reference.");
      }
      break;
    }
    case DeformationType::CylinderRadius:
    case DeformationType::SphereRadius: {
      feature->frame.axisymmetric = true;
      feature->frame.origin = c.point;
      feature->frame.axis = type == SurfaceType::Sphere ? Vec3::UnitZ() : c.axis;
      if (options.type == DeformationType::SphereRadius) {
        for (const index_t r : plan.moved) {
          if (r != control) {
            return Status::failure("SphereRadius moves the sphere alone; " + region_name(regions, r) +
                                   " would follow it (give FollowingRegions empty with the override).");
          }
        }
        break;
      }
      for (const index_t r : plan.moved) {
        if (r == control) continue;
        ProfileLine line;
        const SurfacePrimitive& s = regions.surfaces[r];
        const bool coaxial_torus = s.type == SurfaceType::Torus && s.axis.cross(c.axis).norm() < 1e-3 &&
                                   ((s.point - c.point) - (s.point - c.point).dot(c.axis) * c.axis).norm() < tol;
        if (!coaxial_torus && !profile_line(feature->frame, s, line, 1e-3, tol)) {
          return Status::failure("CylinderRadius: following " + region_name(regions, r) +
                                 " is not coaxial with the cylinder, region " + std::to_string(control) +
                                 "; only coaxial fillets and chamfers can follow a radius change.");
        }
      }
      break;
    }
    case DeformationType::FilletRadius: {
      const Status s = fillet_feature(mesh, regions, graph, plan, *feature);
      if (!s) return s;
      break;
    }
    case DeformationType::ChamferAngle:
    case DeformationType::ChamferLength: {
      const Status s = chamfer_feature(regions, graph, plan, *feature);
      if (!s) return s;
      break;
    }
    case DeformationType::Position:
      feature = std::make_shared<Feature>(*plan.feature);
      break;
  }
  plan.feature = feature;
  plan.solve_moved_interior = true;
  plan.current = measure_dimension(plan, regions.surfaces);
  if (!std::isfinite(plan.current)) {
    return Status::failure("the current dimension could not be measured on region " + std::to_string(control) + ".");
  }
  return Status::success();
}

}  // namespace femorph
