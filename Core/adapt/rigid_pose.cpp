// Rigid poses of the moving object (thesis 3.3: the motion of M_m^O is a
// rigid transformation T_i per step), the motion model of the filter and the
// check of a 4x4 motion-table row.
#include "adapt/adapt.h"

#include <cmath>
#include <sstream>

namespace femorph {

RigidPose RigidPose::inverse() const {
  RigidPose p;
  p.R = R.transpose();
  p.t = -(p.R * t);
  return p;
}

RigidPose RigidPose::after(const RigidPose& other) const {
  RigidPose p;
  p.R = R * other.R;
  p.t = R * other.t + t;
  return p;
}

RigidPose RigidPose::fraction(double s) const {
  // Screw interpolation: rotate by s * angle about the same axis, and move
  // the fixed point of the rotation part along the translation.
  const Eigen::AngleAxisd aa(R);
  RigidPose p;
  p.R = Eigen::AngleAxisd(s * aa.angle(), aa.axis()).toRotationMatrix();
  if (std::abs(aa.angle()) < 1e-12) {
    p.t = s * t;
    return p;
  }
  // x -> R x + t = R (x - c) + c + a*axis with c on the axis: the part of t
  // along the axis is the slide a, the rest fixes c by (I - R) c = t_perp.
  const Vec3 axis = aa.axis();
  const double slide = axis.dot(t);
  const Vec3 t_perp = t - slide * axis;
  const Eigen::Matrix3d M = Eigen::Matrix3d::Identity() - R;
  // (I - R) is singular along the axis; solve in the plane normal to it.
  const Vec3 c = M.completeOrthogonalDecomposition().solve(t_perp);
  p.t = c - p.R * c + s * slide * axis;
  return p;
}

RigidPose RigidMotion::pose(int step) const {
  if (!table.empty()) {
    if (step <= 0) return RigidPose();
    return table[static_cast<std::size_t>(std::min<int>(step, static_cast<int>(table.size()))) - 1];
  }
  RigidPose p;
  const double n = step;
  const double norm = rotation_axis.norm();
  if (norm > 0 && rotation_degrees_per_step != 0)
    p.R = Eigen::AngleAxisd(degrees_to_radians(n * rotation_degrees_per_step), rotation_axis / norm)
              .toRotationMatrix();
  // x_n = c + n t + R (x_0 - c)
  p.t = rotation_center + n * translation_per_step - p.R * rotation_center;
  return p;
}

Status rigid_pose_from_matrix(const double m[16], RigidPose& pose, double tolerance) {
  for (int i = 0; i < 16; ++i)
    if (!std::isfinite(m[i])) return Status::failure("an entry is not a finite number");
  if (std::abs(m[12]) > tolerance || std::abs(m[13]) > tolerance || std::abs(m[14]) > tolerance ||
      std::abs(m[15] - 1) > tolerance) {
    std::ostringstream os;
    os << "its last row is (" << m[12] << " " << m[13] << " " << m[14] << " " << m[15] << "), not (0 0 0 1)";
    return Status::failure(os.str());
  }
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = m[4 * r + c];
  const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality > tolerance) {
    std::ostringstream os;
    os << "its 3x3 part is not a rotation (R^T R differs from the identity by " << orthogonality
       << ": scaling or shear; Adapt moves objects rigidly)";
    return Status::failure(os.str());
  }
  if (R.determinant() < 0) return Status::failure("its 3x3 part is a reflection (determinant -1), not a rotation");
  pose.R = R;
  pose.t = Vec3(m[3], m[7], m[11]);
  return Status::success();
}

}  // namespace femorph
