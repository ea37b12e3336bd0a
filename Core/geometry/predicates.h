// Exact geometric predicates: Shewchuk's adaptive-precision orient3d and
// insphere, as exported by TetGen's libtet. Kept behind this header so that
// tetgen.h (which defines REAL and takes non-const pointers) never reaches a
// public header.
#pragma once

#include <Eigen/Core>

namespace femorph {

/// Sign of the volume of tet (a, b, c, d), computed exactly:
/// +1 when (b - a) . ((c - a) x (d - a)) > 0, which is VTK_TETRA's positive
/// orientation and FEMorph's; 0 when the four points are coplanar; -1 else.
/// Exact at any scale of the coordinates (1e-300 to 1e300): a result that
/// underflowed or overflowed is redone on the points scaled by a power of two.
int orient3d_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, const Eigen::Vector3d& d);

/// Exact in-sphere test for the positively oriented tet (a, b, c, d):
/// +1 when e lies strictly inside its circumsphere, 0 on it, -1 outside.
/// The result is meaningless when (a, b, c, d) is not positively oriented.
int insphere_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                  const Eigen::Vector3d& e);

/// Sign of the area of triangle (a, b, c) in the plane, computed exactly:
/// +1 when counter-clockwise, 0 when collinear, -1 when clockwise.
int orient2d_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c);

/// Exact in-circle test for the counter-clockwise triangle (a, b, c): +1 when
/// d lies strictly inside its circumcircle, 0 on it, -1 outside.
int incircle_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d);

}  // namespace femorph
