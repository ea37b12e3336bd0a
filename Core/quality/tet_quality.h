// Element quality measures (thesis Eq. 1.1 and Eq. 4.2).
//
// Conventions: VTK node orders (VTK_TETRA, VTK_PYRAMID, VTK_WEDGE,
// VTK_HEXAHEDRON); a tet (a, b, c, d) is positive when
// (b - a) . ((c - a) x (d - a)) > 0.
#pragma once

#include "common/types.h"

#include <vector>

namespace femorph {

/// Signed volume of tet (a, b, c, d): (b - a) . ((c - a) x (d - a)) / 6.
double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Stretch, thesis Eq. 1.1: Q = 6 sqrt(6) V / (L_max * A), V the signed volume,
/// L_max the longest edge, A the total surface area of the four faces.
/// 1 for the regular tet, 0 for a flat one, negative when inverted.
/// Returns 0 when the denominator vanishes (all points collinear or equal).
/// Invariant under translation, rotation and uniform scaling.
double tet_stretch(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Minimum and maximum dihedral angle of a tet, in radians, over its six
/// edges (angle between the two faces at the edge, measured inside the tet).
/// Regular tet: acos(1/3) at every edge. A flat tet has min 0 and max pi; a
/// tet with a zero-area face returns exactly {0, pi}. Computed from the
/// unsigned geometry, so an inverted tet gets the angles of its mirror image.
/// Evaluated with atan2(|n_i x n_j|, -n_i . n_j) over face normals, accurate
/// near 0 and pi.
struct DihedralRange {
  double min = 0;
  double max = 0;
};
DihedralRange tet_dihedral_range(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Cell kinds the scaled Jacobian knows, with VTK's node orders.
enum class CellKind { Tetra, Pyramid, Wedge, Hexahedron };

/// Number of nodes of a cell kind (4, 5, 6, 8).
int cell_node_count(CellKind kind);

/// Scaled Jacobian at every corner, thesis Eq. 4.2 (Knupp 2000), not normalised:
///   Q(i) = (x_j1 - x_i) . ((x_j2 - x_i) x (x_j3 - x_i)) / (|x_j1 - x_i| |x_j2 - x_i| |x_j3 - x_i|)
/// with j1, j2, j3 the three edge neighbours of corner i, ordered so that a
/// positively oriented cell gives positive values and a right-angle corner of
/// a rectangular cell gives 1 (orders derived from VTK's node orders, listed
/// in tet_quality.cpp). Values lie in [-1, 1]; 0 where the cell is flat at i.
///   Tetra      4 corners; regular tet sqrt(2)/2 at each (the thesis' 0.707).
///   Pyramid    the 4 base corners only (the apex has four edges, Eq. 4.2
///              does not define it); base (0,1,2,3) normal toward the apex 4.
///   Wedge      6 corners; (0,1,2) normal away from (3,4,5). Right prism over
///              an equilateral triangle: sqrt(3)/2 at each (the thesis' 0.866).
///   Hexahedron 8 corners; (0,1,2,3) normal toward (4,5,6,7). Box: 1 at each.
/// Inputs:
///   kind    cell kind
///   points  cell_node_count(kind) points in VTK order
/// Output:
///   corners as many values as evaluated corners (4, 4, 6, 8), in node order
/// Returns the number of evaluated corners. A corner with a zero-length edge
/// gets 0. For a tet the numerator is six times its signed volume at every
/// corner (each corner order is an even permutation of (0,1,2,3)).
int scaled_jacobian_corners(CellKind kind, const Vec3* points, double* corners);

/// Minimum of scaled_jacobian_corners over the evaluated corners (the
/// element's shape quality in the thesis; -1 <= Q <= 1).
double min_scaled_jacobian(CellKind kind, const Vec3* points);

/// Quality of every tet of a mesh in one parallel pass (common/parallel.h),
/// each tet's edge vectors computed once and shared by the measures.
/// Inputs:
///   points  #V positions
///   tets    #T tets, 0-based ids into points (not checked)
/// Outputs (each may be null to skip that measure; non-null ones hold #T values):
///   stretch              tet_stretch (Eq. 1.1)
///   min_scaled_jacobian  min_scaled_jacobian(CellKind::Tetra, ...) (Eq. 4.2)
///   min_dihedral         tet_dihedral_range().min, radians
///   max_dihedral         tet_dihedral_range().max, radians
///   signed_volume        tet_signed_volume
/// Every value is computed by the same arithmetic as the per-tet function's.
void compute_tet_quality(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                         double* stretch, double* min_scaled_jacobian,
                         double* min_dihedral, double* max_dihedral,
                         double* signed_volume);

}  // namespace femorph
