#include "quality/tet_quality.h"
#include "common/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace femorph {
namespace {

constexpr double kPi = 3.14159265358979323846;
// 2 sqrt(6): Eq. 1.1's 6 sqrt(6) V / (L A) with V = det / 6 and A = S / 2,
// S the sum of the face cross-product norms.
const double kStretchScale = 2.0 * std::sqrt(6.0);

// |u x v| with the components kept in registers. (cross().norm() lets GCC
// store the three components one by one and reload two as a pair: a
// store-forwarding stall in the stretch loop.)
inline double cross_norm(const Vec3& u, const Vec3& v) {
  const double x = u.y() * v.z() - u.z() * v.y();
  const double y = u.z() * v.x() - u.x() * v.z();
  const double z = u.x() * v.y() - u.y() * v.x();
  return std::sqrt(x * x + y * y + z * z);
}

// Scale-free measures: every measure here is a ratio of products of up to
// four edge lengths (det / (L_max * S), normals' cross products), so with
// edges near 1e-300 the products underflow to 0 and near 1e300 they overflow
// (every tet came out flat at either scale). A cell whose longest
// edge lies outside [2^-200, 2^200] is first scaled by a power of two, which
// is exact and leaves every ratio as it is; cells inside the range (all
// ordinary meshes) are computed exactly as before.
constexpr double kMinSquaredLength = 0x1p-400;
constexpr double kMaxSquaredLength = 0x1p400;

// The exponent k for which 2^k brings `largest` (> 0, finite) into [0.5, 1).
inline int scale_exponent(double largest) {
  int exponent = 0;
  std::frexp(largest, &exponent);
  return -exponent;
}

inline double power_of_two_scale(double largest) { return std::ldexp(1.0, scale_exponent(largest)); }

// The six edge vectors of tet (a, b, c, d), computed once and shared by every
// measure of the tet; scaled by a power of two when their lengths are out of
// range (see kMinSquaredLength).
struct TetEdges {
  Vec3 ab, ac, ad, bc, bd, cd;
  double max_squared;  // of the (scaled) edges
  int exponent = 0;    // the edges are 2^exponent times the tet's

  TetEdges(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
      : ab(b - a), ac(c - a), ad(d - a), bc(c - b), bd(d - b), cd(d - c) {
    max_squared = max_squared_length();
    // Also taken when a squared length overflowed to infinity.
    if (!(max_squared >= kMinSquaredLength && max_squared <= kMaxSquaredLength)) rescale();
  }

  // Six times the signed volume (of the scaled edges).
  double det() const { return ab.dot(ac.cross(ad)); }

  // The tet's own signed volume from det() (0 or infinite where it is not
  // representable).
  double volume(double det) const { return std::ldexp(det / 6.0, -3 * exponent); }

  double max_squared_length() const {
    return std::max({ab.squaredNorm(), ac.squaredNorm(), ad.squaredNorm(),
                     bc.squaredNorm(), bd.squaredNorm(), cd.squaredNorm()});
  }

 private:
  void rescale() {
    double largest = 0;
    for (const Vec3* e : {&ab, &ac, &ad, &bc, &bd, &cd}) largest = std::max(largest, e->cwiseAbs().maxCoeff());
    if (!(largest > 0) || !std::isfinite(largest)) return;  // all points equal, or NaN
    exponent = scale_exponent(largest);
    const double s = std::ldexp(1.0, exponent);
    for (Vec3* e : {&ab, &ac, &ad, &bc, &bd, &cd}) *e *= s;
    max_squared = max_squared_length();
  }

 public:

  // Face normals (twice the area vectors), opposite a, b, c, d in turn;
  // outward for a positive tet, all inward for an inverted one.
  Vec3 normal_a() const { return bc.cross(bd); }
  Vec3 normal_b() const { return ad.cross(ac); }
  Vec3 normal_c() const { return ab.cross(ad); }
  Vec3 normal_d() const { return ac.cross(ab); }
};

// Eq. 1.1 from the edges and det = 6 V; the face areas are the normals'
// norms over 2 (cross_norm of normal_a() ... normal_d()'s factors).
double stretch_of(const TetEdges& e, double det) {
  const double l_max = std::sqrt(e.max_squared);
  const double s = cross_norm(e.bc, e.bd) + cross_norm(e.ad, e.ac) + cross_norm(e.ab, e.ad) +
                   cross_norm(e.ac, e.ab);
  const double denominator = l_max * s;
  return denominator > 0 ? kStretchScale * det / denominator : 0.0;
}

// Eq. 4.2 at the four corners of a tet. Each corner's neighbours are an even
// permutation of the tet's, so the numerator is the same det at all four;
// only the edge-length products differ.
void tet_corner_jacobians(const TetEdges& e, double det, double* corners) {
  const double l_ab = e.ab.norm(), l_ac = e.ac.norm(), l_ad = e.ad.norm();
  const double l_bc = e.bc.norm(), l_bd = e.bd.norm(), l_cd = e.cd.norm();
  const double lengths[4] = {l_ab * l_ac * l_ad, l_ab * l_bc * l_bd, l_ac * l_bc * l_cd,
                             l_ad * l_bd * l_cd};
  for (int i = 0; i < 4; ++i) corners[i] = lengths[i] > 0 ? det / lengths[i] : 0.0;
}

double tet_min_jacobian(const TetEdges& e, double det) {
  double corners[4];
  tet_corner_jacobians(e, det, corners);
  return std::min({corners[0], corners[1], corners[2], corners[3]});
}

// Interior dihedral angle between faces i and j: pi minus the angle of their
// outward unit normals, so cos = -n_i . n_j and sin = |n_i x n_j|; atan2 keeps
// it accurate near 0 and pi, where acos is not. The extremes are picked
// without six atan2 calls by ranking each angle with a key that increases
// with it: sin up to pi/2, 2 - sin beyond.
DihedralRange dihedral_range_of(const TetEdges& e) {
  const Vec3 n[4] = {e.normal_a(), e.normal_b(), e.normal_c(), e.normal_d()};
  double inverse_length[4];
  for (int i = 0; i < 4; ++i) {
    const double length = n[i].norm();
    if (length == 0) return {0.0, kPi};  // a face has no area: the tet is flat
    inverse_length[i] = 1.0 / length;
  }
  static constexpr int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  double cosine[6], sine[6], key[6];
  for (int k = 0; k < 6; ++k) {
    const int i = kPairs[k][0], j = kPairs[k][1];
    const double scale = inverse_length[i] * inverse_length[j];
    cosine[k] = -n[i].dot(n[j]) * scale;
    sine[k] = cross_norm(n[i], n[j]) * scale;
    key[k] = cosine[k] >= 0 ? sine[k] : 2 - sine[k];
  }
  int lo = 0, hi = 0;
  for (int k = 1; k < 6; ++k) {
    lo = key[k] < key[lo] ? k : lo;
    hi = key[k] > key[hi] ? k : hi;
  }
  return {std::atan2(sine[lo], cosine[lo]), std::atan2(sine[hi], cosine[hi])};
}

// Eq. 4.2 neighbour orders (j1, j2, j3) per corner, from VTK's node orders:
// (x_j1 - x_i) . ((x_j2 - x_i) x (x_j3 - x_i)) > 0 on a positive cell and = 1
// at a right-angle corner of a rectangular one.
//  - Pyramid: base (0,1,2,3) counter-clockwise seen from the apex 4; base
//    corner k takes (next, previous, apex), the apex is not evaluated.
//  - Wedge: (0,1,2) clockwise seen from (3,4,5), node k + 3 above node k;
//    bottom corner k takes (previous, next, k + 3), top corner 3 + k takes
//    (3 + next, 3 + previous, k).
//  - Hexahedron: (0,1,2,3) counter-clockwise seen from (4,5,6,7), node k + 4
//    above node k; bottom corner k takes (next, previous, k + 4), top corner
//    4 + k takes (4 + previous, 4 + next, k).
constexpr int kPyramidCorners[4][3] = {{1, 3, 4}, {2, 0, 4}, {3, 1, 4}, {0, 2, 4}};
constexpr int kWedgeCorners[6][3] = {{2, 1, 3}, {0, 2, 4}, {1, 0, 5},
                                     {4, 5, 0}, {5, 3, 1}, {3, 4, 2}};
constexpr int kHexCorners[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                                   {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};

// Eq. 4.2 at corner i with neighbours j[0..2]; 0 when an edge has no length.
double corner_jacobian(const Vec3* x, int i, const int* j) {
  const Vec3 e1 = x[j[0]] - x[i], e2 = x[j[1]] - x[i], e3 = x[j[2]] - x[i];
  const double lengths = e1.norm() * e2.norm() * e3.norm();
  return lengths > 0 ? e1.dot(e2.cross(e3)) / lengths : 0.0;
}

// Eq. 4.2 at the N evaluated corners of a cell of `nodes` nodes. Scale-free as TetEdges:
// a cell whose coordinates all lie below 2^-200 or reach beyond 2^200 in
// magnitude is scaled by a power of two first (its edges cannot be shorter
// than its coordinates' precision, so the largest coordinate bounds them).
template <int N>
int corner_jacobians(const Vec3* x, int nodes, const int (&table)[N][3], double* corners) {
  double largest = 0;
  for (int i = 0; i < nodes; ++i) largest = std::max(largest, x[i].cwiseAbs().maxCoeff());
  if (largest > 0 && std::isfinite(largest) && (largest < 0x1p-200 || largest > 0x1p200)) {
    const double s = power_of_two_scale(largest);
    Vec3 scaled[8];  // every node, the pyramid's apex too (N counts corners)
    for (int i = 0; i < nodes; ++i) scaled[i] = x[i] * s;
    for (int i = 0; i < N; ++i) corners[i] = corner_jacobian(scaled, i, table[i]);
    return N;
  }
  for (int i = 0; i < N; ++i) corners[i] = corner_jacobian(x, i, table[i]);
  return N;
}

}  // namespace

double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

double tet_stretch(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const TetEdges e(a, b, c, d);
  return stretch_of(e, e.det());
}

DihedralRange tet_dihedral_range(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return dihedral_range_of(TetEdges(a, b, c, d));
}

int cell_node_count(CellKind kind) {
  switch (kind) {
    case CellKind::Tetra: return 4;
    case CellKind::Pyramid: return 5;
    case CellKind::Wedge: return 6;
    case CellKind::Hexahedron: return 8;
  }
  return 0;
}

int scaled_jacobian_corners(CellKind kind, const Vec3* points, double* corners) {
  switch (kind) {
    case CellKind::Tetra: {
      const TetEdges e(points[0], points[1], points[2], points[3]);
      tet_corner_jacobians(e, e.det(), corners);
      return 4;
    }
    case CellKind::Pyramid: return corner_jacobians(points, 5, kPyramidCorners, corners);
    case CellKind::Wedge: return corner_jacobians(points, 6, kWedgeCorners, corners);
    case CellKind::Hexahedron: return corner_jacobians(points, 8, kHexCorners, corners);
  }
  return 0;
}

double min_scaled_jacobian(CellKind kind, const Vec3* points) {
  if (kind == CellKind::Tetra) {
    const TetEdges e(points[0], points[1], points[2], points[3]);
    return tet_min_jacobian(e, e.det());
  }
  double corners[8];
  const int count = scaled_jacobian_corners(kind, points, corners);
  return *std::min_element(corners, corners + count);
}

void compute_tet_quality(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                         double* stretch, double* min_scaled_jacobian,
                         double* min_dihedral, double* max_dihedral,
                         double* signed_volume) {
  const bool want_dihedral = min_dihedral || max_dihedral;
  const std::int64_t count = static_cast<std::int64_t>(tets.size());
  parallel_for(static_cast<long>(count), [&](long t) {
    const Tet& tet = tets[static_cast<std::size_t>(t)];
    const TetEdges e(points[tet[0]], points[tet[1]], points[tet[2]], points[tet[3]]);
    const double det = e.det();
    if (signed_volume) signed_volume[t] = e.volume(det);
    if (stretch) stretch[t] = stretch_of(e, det);
    if (min_scaled_jacobian) min_scaled_jacobian[t] = tet_min_jacobian(e, det);
    if (want_dihedral) {
      const DihedralRange range = dihedral_range_of(e);
      if (min_dihedral) min_dihedral[t] = range.min;
      if (max_dihedral) max_dihedral[t] = range.max;
    }
  });
}

}  // namespace femorph
