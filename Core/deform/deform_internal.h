// Geometry shared by the steps of Deform: the 2D profile of an
// axisymmetric or prismatic feature, in which planes, cylinders and cones
// are lines and fillets are circles (Table 2.7's parameter changes are 2D
// constructions there), and the feature record of a plan.
#pragma once

#include "deform/deform.h"

#include <Eigen/Core>

namespace femorph {

using Vec2 = Eigen::Vector2d;

/// Axisymmetric: coordinates (rho, z) about the line (origin, axis).
/// Prismatic: (u, v) in the plane through origin normal to axis (a
/// direction), along e1, e2. The third coordinate (angle about the axis, or
/// position along it) is what a mapped point keeps.
struct ProfileFrame {
  bool axisymmetric = true;
  Vec3 origin = Vec3::Zero(), axis = Vec3::UnitZ(), e1 = Vec3::UnitX(), e2 = Vec3::UnitY();
  Vec2 to2d(const Vec3& p) const;
  /// The point with profile coordinates q and the third coordinate of `like`.
  Vec3 from2d(const Vec2& q, const Vec3& like) const;
  static ProfileFrame prismatic(const Vec3& origin, const Vec3& direction);
};

/// A line of the profile: signed distance n . q + c (n unit), with the
/// sign of the surface's own signed distance (positive where its normal
/// points).
struct ProfileLine {
  Vec2 n = Vec2::Zero();
  double c = 0;
  double distance(const Vec2& q) const { return n.dot(q) + c; }
};

/// The profile line of a plane, cylinder or cone in `frame` (planes normal
/// to an axisymmetric frame's axis, coaxial cylinders and cones; planes
/// parallel to a prismatic frame's direction); false for other surfaces.
bool profile_line(const ProfileFrame& frame, const SurfacePrimitive& s, ProfileLine& line, double angle_tol = 1e-3,
                  double position_tol = 1e-6);

/// The point at signed distances da, db from two profile lines (false when
/// they are parallel).
bool offset_intersection(const ProfileLine& a, double da, const ProfileLine& b, double db, Vec2& q);

/// The largest distance a vertex of a moved region travels for `update`
/// (the reach of the deformable region).
double largest_move(const TetMesh& mesh, const DeformPlan& plan, const SurfaceUpdate& update);

/// Mean edge length of the live tets.
double mean_edge_length(const TetMesh& mesh);

struct DeformPlan::Feature {
  /// Distance / Position: unit direction in which the dimension grows
  /// (Distance: from the reference plane to the control plane).
  Vec3 direction = Vec3::Zero();
  /// CylinderRadius, SphereRadius: the control's axis or centre.
  ProfileFrame frame;
  /// FilletRadius: per moved region, the circle of its profile and the two
  /// lines it is tangent to (signs: the side of each line the centre is on).
  struct Fillet {
    index_t region = kInvalidIndex;
    ProfileFrame frame;
    ProfileLine a, b;
    double sa = 1, sb = 1;
    Vec2 center = Vec2::Zero();
    double radius = 0;
    /// Prismatic fillets ending at equal-radius sphere corners: the range
    /// of the axial coordinate and the sphere at each end (-1: none).
    double t_lo = 0, t_hi = 0;
    index_t sphere_lo = kInvalidIndex, sphere_hi = kInvalidIndex;
  };
  std::vector<Fillet> fillets;
  /// FilletRadius: following spheres and the fillets (indices into
  /// `fillets`) whose axes meet at their centres.
  struct Corner {
    index_t region = kInvalidIndex;
    std::vector<int> fillets;
  };
  std::vector<Corner> corners;
  /// Chamfers: the profile lines of the reference face (R) and of the other
  /// face (O), the edge E the chamfer replaced, the chamfer's ends A (on R)
  /// and B (on O) and the angle gamma at E between R and O.
  ProfileLine line_r, line_o;
  Vec2 edge = Vec2::Zero(), end_a = Vec2::Zero(), end_b = Vec2::Zero();
  double gamma = 0;
  index_t other_region = kInvalidIndex;
};

}  // namespace femorph
