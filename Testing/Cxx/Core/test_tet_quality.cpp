// Quality measures (thesis Eq. 1.1 stretch, Eq. 4.2 scaled Jacobian, dihedral
// angles): closed forms on canonical cells, signs on mirrored cells,
// invariance under similarity transforms, and the batch function against the
// per-tet functions.
#include "quality/tet_quality.h"
#include "geometry/predicates.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace femorph {
namespace {

const double kPi = std::acos(-1.0);
const double kSqrt2 = std::sqrt(2.0);
const double kSqrt3 = std::sqrt(3.0);

using TetPoints = std::array<Vec3, 4>;

double volume6(const TetPoints& p) {
  return (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]));
}

// Regular tet with edge 2 sqrt(2), positively oriented.
TetPoints regular_tet() {
  TetPoints p = {Vec3(1, 1, 1), Vec3(-1, 1, -1), Vec3(1, -1, -1), Vec3(-1, -1, 1)};
  EXPECT_GT(volume6(p), 0);
  return p;
}

// The right-corner tet (0, e1, e2, e3), positive.
TetPoints corner_tet() {
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
}

double stretch(const TetPoints& p) { return tet_stretch(p[0], p[1], p[2], p[3]); }
DihedralRange dihedral(const TetPoints& p) { return tet_dihedral_range(p[0], p[1], p[2], p[3]); }

std::vector<double> corners(CellKind kind, const std::vector<Vec3>& points) {
  EXPECT_EQ(static_cast<int>(points.size()), cell_node_count(kind));
  std::vector<double> values(8, 99.0);
  values.resize(scaled_jacobian_corners(kind, points.data(), values.data()));
  return values;
}

// Random tet near the regular one (so every measure is well conditioned).
TetPoints jittered_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  TetPoints p = regular_tet();
  for (Vec3& x : p) x += Vec3(jitter(rng), jitter(rng), jitter(rng));
  return p;
}

// Eq. 1.1 written out term by term, independently of the library's factoring.
double stretch_reference(const TetPoints& p) {
  const double volume = volume6(p) / 6.0;
  double area = 0, longest = 0;
  const int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (const auto& f : faces)
    area += 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) longest = std::max(longest, (p[j] - p[i]).norm());
  return 6.0 * std::sqrt(6.0) * volume / (longest * area);
}

// The six dihedral angles by projecting the two opposite vertices onto the
// plane normal to the edge and measuring the angle between them there.
std::array<double, 6> dihedral_reference(const TetPoints& p) {
  std::array<double, 6> angles{};
  int k = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      int others[2], n = 0;
      for (int m = 0; m < 4; ++m)
        if (m != i && m != j) others[n++] = m;
      const Vec3 axis = (p[j] - p[i]).normalized();
      Vec3 u = p[others[0]] - p[i], v = p[others[1]] - p[i];
      u -= axis * axis.dot(u);
      v -= axis * axis.dot(v);
      angles[k++] = std::acos(std::clamp(u.normalized().dot(v.normalized()), -1.0, 1.0));
    }
  return angles;
}

// ---------------------------------------------------------------- stretch

TEST(TetStretch, RegularTetIsOne) {
  EXPECT_NEAR(stretch(regular_tet()), 1.0, 1e-14);
}

TEST(TetStretch, FlatTetIsZero) {
  // d inside triangle abc, and four points of a square (convex position).
  EXPECT_EQ(stretch({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.3, 0)}), 0.0);
  EXPECT_EQ(stretch({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}), 0.0);
}

TEST(TetStretch, NoExtentIsZero) {
  const Vec3 x(1, 2, 3);
  EXPECT_EQ(stretch({x, x, x, x}), 0.0);
  EXPECT_EQ(stretch({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)}), 0.0);
}

TEST(TetStretch, InvertedIsNegative) {
  TetPoints p = regular_tet();
  std::swap(p[0], p[1]);
  EXPECT_NEAR(stretch(p), -1.0, 1e-14);
  TetPoints q = corner_tet();
  std::swap(q[2], q[3]);
  EXPECT_LT(stretch(q), 0.0);
  EXPECT_NEAR(stretch(q), -stretch(corner_tet()), 1e-15);
}

TEST(TetStretch, CornerTetClosedForm) {
  // V = 1/6, L_max = sqrt(2), A = 3/2 + sqrt(3)/2.
  const double expected = std::sqrt(6.0) / (kSqrt2 * (1.5 + kSqrt3 / 2));
  EXPECT_NEAR(stretch(corner_tet()), expected, 1e-15);
}

TEST(TetStretch, MatchesEquationTermByTerm) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1, 1);
  for (int n = 0; n < 200; ++n) {
    TetPoints p;
    for (Vec3& x : p) x = Vec3(coord(rng), coord(rng), coord(rng));
    EXPECT_NEAR(stretch(p), stretch_reference(p), 1e-12);
  }
}

TEST(TetSignedVolume, CornerTet) {
  const TetPoints p = corner_tet();
  EXPECT_DOUBLE_EQ(tet_signed_volume(p[0], p[1], p[2], p[3]), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(tet_signed_volume(p[1], p[0], p[2], p[3]), -1.0 / 6.0);
}

// ------------------------------------------------------- scaled Jacobian

TEST(ScaledJacobian, NodeCounts) {
  EXPECT_EQ(cell_node_count(CellKind::Tetra), 4);
  EXPECT_EQ(cell_node_count(CellKind::Pyramid), 5);
  EXPECT_EQ(cell_node_count(CellKind::Wedge), 6);
  EXPECT_EQ(cell_node_count(CellKind::Hexahedron), 8);
}

TEST(ScaledJacobian, RegularTetIsHalfSqrt2) {
  const TetPoints p = regular_tet();
  const std::vector<double> q = corners(CellKind::Tetra, {p.begin(), p.end()});
  ASSERT_EQ(q.size(), 4u);
  for (double v : q) EXPECT_NEAR(v, kSqrt2 / 2, 1e-14);
  EXPECT_NEAR(min_scaled_jacobian(CellKind::Tetra, p.data()), kSqrt2 / 2, 1e-14);
}

TEST(ScaledJacobian, CornerTetClosedForm) {
  // Right-angle corner 1; the other corners see edges 1, sqrt2, sqrt2.
  const TetPoints p = corner_tet();
  const std::vector<double> q = corners(CellKind::Tetra, {p.begin(), p.end()});
  EXPECT_NEAR(q[0], 1.0, 1e-15);
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(q[i], 0.5, 1e-15);
}

TEST(ScaledJacobian, TetCornersFollowEquation) {
  // Eq. 4.2 at each corner with neighbours an even permutation of (0,1,2,3).
  const int order[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-1, 1);
  for (int n = 0; n < 100; ++n) {
    TetPoints p;
    for (Vec3& x : p) x = Vec3(coord(rng), coord(rng), coord(rng));
    const std::vector<double> q = corners(CellKind::Tetra, {p.begin(), p.end()});
    for (int c = 0; c < 4; ++c) {
      const Vec3 e1 = p[order[c][1]] - p[order[c][0]], e2 = p[order[c][2]] - p[order[c][0]],
                 e3 = p[order[c][3]] - p[order[c][0]];
      EXPECT_NEAR(q[c], e1.dot(e2.cross(e3)) / (e1.norm() * e2.norm() * e3.norm()), 1e-12);
    }
  }
}

TEST(ScaledJacobian, InvertedTetIsNegative) {
  TetPoints p = regular_tet();
  std::swap(p[2], p[3]);
  for (double v : corners(CellKind::Tetra, {p.begin(), p.end()}))
    EXPECT_NEAR(v, -kSqrt2 / 2, 1e-14);
}

std::vector<Vec3> box_hex(double lx, double ly, double lz) {
  return {Vec3(0, 0, 0),  Vec3(lx, 0, 0),  Vec3(lx, ly, 0),  Vec3(0, ly, 0),
          Vec3(0, 0, lz), Vec3(lx, 0, lz), Vec3(lx, ly, lz), Vec3(0, ly, lz)};
}

TEST(ScaledJacobian, UnitCubeHexIsOne) {
  const std::vector<double> q = corners(CellKind::Hexahedron, box_hex(1, 1, 1));
  ASSERT_EQ(q.size(), 8u);
  for (double v : q) EXPECT_EQ(v, 1.0);
}

TEST(ScaledJacobian, BoxHexIsOne) {
  for (double v : corners(CellKind::Hexahedron, box_hex(1, 2, 3))) EXPECT_NEAR(v, 1.0, 1e-15);
}

TEST(ScaledJacobian, MirroredHexIsMinusOne) {
  // Top and bottom swapped: (0,1,2,3)'s normal points away from (4,5,6,7).
  std::vector<Vec3> x = box_hex(1, 1, 1);
  std::rotate(x.begin(), x.begin() + 4, x.end());
  for (double v : corners(CellKind::Hexahedron, x)) EXPECT_EQ(v, -1.0);
}

TEST(ScaledJacobian, ShearedHexClosedForm) {
  // Top face shifted by s along x: every corner sees two unit axis edges and
  // the slanted edge +-(s, 0, 1): Q = 1 / sqrt(1 + s^2) everywhere.
  const double s = 0.5;
  std::vector<Vec3> x = box_hex(1, 1, 1);
  for (int k = 4; k < 8; ++k) x[k].x() += s;
  for (double v : corners(CellKind::Hexahedron, x)) EXPECT_NEAR(v, 1 / std::sqrt(1 + s * s), 1e-15);
}

// Right prism of height h over triangle (p0, p1, p2), clockwise seen from
// above so that (0,1,2)'s normal points away from the top (VTK_WEDGE).
std::vector<Vec3> prism(const Vec3& p0, const Vec3& p1, const Vec3& p2, double h) {
  const Vec3 up(0, 0, h);
  return {p0, p1, p2, p0 + up, p1 + up, p2 + up};
}

TEST(ScaledJacobian, RightIsoscelesWedge) {
  // Right angle at node 0 (and 3 above it): 1 there; sqrt(2)/2 at the 45
  // degree corners.
  const std::vector<Vec3> x = prism(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), 2.0);
  const std::vector<double> q = corners(CellKind::Wedge, x);
  ASSERT_EQ(q.size(), 6u);
  const double expected[6] = {1, kSqrt2 / 2, kSqrt2 / 2, 1, kSqrt2 / 2, kSqrt2 / 2};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(q[i], expected[i], 1e-15) << "corner " << i;
}

TEST(ScaledJacobian, EquilateralWedge) {
  const std::vector<Vec3> x = prism(Vec3(0, 0, 0), Vec3(0.5, kSqrt3 / 2, 0), Vec3(1, 0, 0), 0.7);
  for (double v : corners(CellKind::Wedge, x)) EXPECT_NEAR(v, kSqrt3 / 2, 1e-15);
  EXPECT_NEAR(min_scaled_jacobian(CellKind::Wedge, x.data()), kSqrt3 / 2, 1e-15);
}

TEST(ScaledJacobian, MirroredWedgeIsNegative) {
  // Bottom and top swapped: (0,1,2)'s normal now points toward (3,4,5).
  std::vector<Vec3> x = prism(Vec3(0, 0, 0), Vec3(0.5, kSqrt3 / 2, 0), Vec3(1, 0, 0), 1.0);
  std::rotate(x.begin(), x.begin() + 3, x.end());
  for (double v : corners(CellKind::Wedge, x)) EXPECT_NEAR(v, -kSqrt3 / 2, 1e-15);
}

TEST(ScaledJacobian, SquarePyramid) {
  // Base (+-1, +-1, 0) counter-clockwise seen from the apex (0, 0, h). At
  // corner 0: edges (2,0,0), (0,2,0), (1,1,h); triple product 4h, lengths
  // 2 * 2 * sqrt(2 + h^2): Q = h / sqrt(2 + h^2) at every base corner.
  const double h = 1.5;
  std::vector<Vec3> x = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0),
                         Vec3(0, 0, h)};
  const double expected = h / std::sqrt(2 + h * h);
  const std::vector<double> q = corners(CellKind::Pyramid, x);
  ASSERT_EQ(q.size(), 4u);  // the apex is not evaluated
  for (double v : q) EXPECT_NEAR(v, expected, 1e-15);

  x[4].z() = -h;  // apex below: the base normal points away from it
  for (double v : corners(CellKind::Pyramid, x)) EXPECT_NEAR(v, -expected, 1e-15);
}

TEST(ScaledJacobian, ZeroLengthEdgeGivesZero) {
  std::vector<Vec3> hex = box_hex(1, 1, 1);
  hex[1] = hex[0];
  const std::vector<double> q = corners(CellKind::Hexahedron, hex);
  EXPECT_EQ(q[0], 0.0);
  EXPECT_EQ(q[1], 0.0);
  for (int i = 2; i < 8; ++i) EXPECT_TRUE(std::isfinite(q[i]));

  TetPoints p = corner_tet();
  p[3] = p[2];
  for (double v : corners(CellKind::Tetra, {p.begin(), p.end()})) EXPECT_EQ(v, 0.0);
  const Vec3 same(1, 2, 3);
  const std::vector<Vec3> point = {same, same, same, same};
  EXPECT_EQ(min_scaled_jacobian(CellKind::Tetra, point.data()), 0.0);
}

// ------------------------------------------------------ dihedral angles

TEST(TetDihedral, RegularTet) {
  const DihedralRange r = dihedral(regular_tet());
  EXPECT_NEAR(r.min, std::acos(1.0 / 3.0), 1e-14);
  EXPECT_NEAR(r.max, std::acos(1.0 / 3.0), 1e-14);
}

TEST(TetDihedral, CornerTet) {
  // pi/2 at the three edges through the origin, acos(1/sqrt 3) at the others.
  const std::array<double, 6> all = dihedral_reference(corner_tet());
  int right = 0, other = 0;
  for (double a : all) {
    right += std::abs(a - kPi / 2) < 1e-14;
    other += std::abs(a - std::acos(1 / kSqrt3)) < 1e-14;
  }
  EXPECT_EQ(right, 3);
  EXPECT_EQ(other, 3);
  const DihedralRange r = dihedral(corner_tet());
  EXPECT_NEAR(r.min, std::acos(1 / kSqrt3), 1e-15);
  EXPECT_NEAR(r.max, kPi / 2, 1e-15);
}

TEST(TetDihedral, InvertedTetGetsMirrorAngles) {
  TetPoints p = corner_tet();
  std::swap(p[0], p[3]);
  const DihedralRange r = dihedral(p);
  EXPECT_NEAR(r.min, std::acos(1 / kSqrt3), 1e-15);
  EXPECT_NEAR(r.max, kPi / 2, 1e-15);
}

TEST(TetDihedral, FlatTets) {
  for (const TetPoints& p :
       {TetPoints{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.3, 0)},
        TetPoints{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)},
        TetPoints{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)},   // zero-area face
        TetPoints{Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}}) {  // zero edge
    const DihedralRange r = dihedral(p);
    EXPECT_NEAR(r.min, 0.0, 1e-15);
    EXPECT_NEAR(r.max, kPi, 1e-15);
  }
}

TEST(TetDihedral, NearlyFlatIsAccurate) {
  // Apex at height h above the centroid of the corner triangle: the smallest
  // angles, at the edges on the axes, are atan(3h); acos-based formulas lose
  // them entirely at this h.
  for (double h : {1e-3, 1e-6, 1e-9, 1e-12}) {
    const TetPoints p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1.0 / 3, 1.0 / 3, h)};
    const DihedralRange r = dihedral(p);
    EXPECT_NEAR(r.min / std::atan(3 * h), 1.0, 1e-9) << "h = " << h;
    EXPECT_GT(r.max, kPi - 100 * h);
    EXPECT_LT(r.max, kPi);
  }
}

TEST(TetDihedral, MatchesProjectionReference) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-1, 1);
  for (int n = 0; n < 200; ++n) {
    TetPoints p;
    for (Vec3& x : p) x = Vec3(coord(rng), coord(rng), coord(rng));
    const std::array<double, 6> all = dihedral_reference(p);
    const DihedralRange r = dihedral(p);
    EXPECT_NEAR(r.min, *std::min_element(all.begin(), all.end()), 1e-9);
    EXPECT_NEAR(r.max, *std::max_element(all.begin(), all.end()), 1e-9);
  }
}

// ----------------------------------------------------------- invariance

TEST(TetQuality, InvariantUnderSimilarity) {
  std::mt19937 rng(5);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const Vec3 shift(12.5, -3.25, 7.0);
  auto expect_relative = [](double a, double b, const char* what) {
    EXPECT_NEAR(a, b, 1e-12 * std::abs(b)) << what;
  };
  for (int n = 0; n < 50; ++n) {
    TetPoints p = jittered_tet(rng);
    if (n % 2) std::swap(p[0], p[1]);  // inverted tets too
    const double s0 = stretch(p);
    const double j0 = min_scaled_jacobian(CellKind::Tetra, p.data());
    const DihedralRange d0 = dihedral(p);
    const std::array<std::function<Vec3(const Vec3&)>, 4> transforms = {
        [&](const Vec3& x) { return Vec3(x + shift); },
        [&](const Vec3& x) { return Vec3(rotation * x); },
        [](const Vec3& x) { return Vec3(1e8 * x); },
        [](const Vec3& x) { return Vec3(1e-8 * x); }};
    for (const auto& transform : transforms) {
      TetPoints q;
      for (int i = 0; i < 4; ++i) q[i] = transform(p[i]);
      expect_relative(stretch(q), s0, "stretch");
      expect_relative(min_scaled_jacobian(CellKind::Tetra, q.data()), j0, "scaled Jacobian");
      expect_relative(dihedral(q).min, d0.min, "min dihedral");
      expect_relative(dihedral(q).max, d0.max, "max dihedral");
    }
  }
}

TEST(TetQuality, HexInvariantUnderSimilarity) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(-1.1, Vec3(0.3, 1, 2).normalized()).toRotationMatrix();
  std::vector<Vec3> hex = box_hex(1, 2, 3);
  hex[6] += Vec3(0.2, -0.1, 0.3);  // not a box any more
  const std::vector<double> q0 = corners(CellKind::Hexahedron, hex);
  for (double scale : {1e8, 1e-8}) {
    std::vector<Vec3> x = hex;
    for (Vec3& p : x) p = scale * (rotation * p) + Vec3(1, 2, 3) * scale;
    const std::vector<double> q = corners(CellKind::Hexahedron, x);
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(q[i], q0[i], 1e-12 * std::abs(q0[i]));
  }
}

// Issue 29: at 1e-300 and 1e300 the products of edge lengths under- and
// overflow, and every tet came out flat (stretch 0, zero volume). Every
// measure, the batch function and the exact orientation are scale-free from
// 1e-300 to 1e300; 1e-12 and 1e12 are the ordinary range's control.
TEST(TetQuality, ScaleFreeFrom1eMinus300To1e300) {
  std::mt19937 rng(29);
  std::vector<TetPoints> tets;
  for (int n = 0; n < 20; ++n) {
    TetPoints p = jittered_tet(rng);
    if (n % 2) std::swap(p[0], p[1]);  // inverted tets too
    tets.push_back(p);
  }
  std::vector<Vec3> hex = box_hex(1, 2, 3);
  hex[6] += Vec3(0.2, -0.1, 0.3);
  const std::vector<double> hex0 = corners(CellKind::Hexahedron, hex);
  for (const double scale : {1e-300, 1e300, 1e-12, 1e12}) {
    SCOPED_TRACE(scale);
    std::vector<Vec3> points;
    std::vector<Tet> batch;
    for (const TetPoints& p : tets) {
      TetPoints q;
      for (int i = 0; i < 4; ++i) q[i] = scale * p[i];
      EXPECT_NEAR(stretch(q), stretch(p), 1e-12 * std::abs(stretch(p)));
      EXPECT_NEAR(min_scaled_jacobian(CellKind::Tetra, q.data()), min_scaled_jacobian(CellKind::Tetra, p.data()),
                  1e-12);
      EXPECT_NEAR(dihedral(q).min, dihedral(p).min, 1e-12);
      EXPECT_NEAR(dihedral(q).max, dihedral(p).max, 1e-12);
      EXPECT_EQ(orient3d_sign(q[0], q[1], q[2], q[3]), volume6(p) > 0 ? 1 : -1);
      const index_t first = static_cast<index_t>(points.size());
      points.insert(points.end(), q.begin(), q.end());
      batch.push_back({first, first + 1, first + 2, first + 3});
    }
    std::vector<double> s(batch.size()), volume(batch.size());
    compute_tet_quality(points, batch, s.data(), nullptr, nullptr, nullptr, volume.data());
    for (std::size_t t = 0; t < batch.size(); ++t) {
      EXPECT_NEAR(s[t], stretch(tets[t]), 1e-12);
      // The volume itself is 1e-900 or 1e900: not representable, but of the
      // right sign (or 0 / infinite), never NaN.
      EXPECT_FALSE(std::isnan(volume[t]));
      EXPECT_GE(volume[t] * volume6(tets[t]), 0.0);
    }
    std::vector<Vec3> x = hex;
    for (Vec3& p : x) p *= scale;
    const std::vector<double> q = corners(CellKind::Hexahedron, x);
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(q[i], hex0[i], 1e-12);
    // A pyramid: its apex (node 4) is scaled too.
    std::vector<Vec3> pyramid = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0.5, 0.5, 1)};
    const double pyramid0 = min_scaled_jacobian(CellKind::Pyramid, pyramid.data());
    for (Vec3& p : pyramid) p *= scale;
    EXPECT_NEAR(min_scaled_jacobian(CellKind::Pyramid, pyramid.data()), pyramid0, 1e-12);
    // A flat tet stays flat at every scale.
    const TetPoints flat = {Vec3(0, 0, 0) * scale, Vec3(1, 0, 0) * scale, Vec3(0, 1, 0) * scale,
                            Vec3(1, 1, 0) * scale};
    EXPECT_EQ(orient3d_sign(flat[0], flat[1], flat[2], flat[3]), 0);
    EXPECT_EQ(stretch(flat), 0.0);
  }
}

// --------------------------------------------------------- batch function

TEST(ComputeTetQuality, EqualsPerTetFunctions) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> coord(-1, 1);
  std::uniform_int_distribution<index_t> pick(0, 99);
  std::vector<Vec3> points(100);
  for (Vec3& x : points) x = Vec3(coord(rng), coord(rng), coord(rng));
  points[7] = points[3];  // a repeated point: zero-length edges
  std::vector<Tet> tets(400);
  for (Tet& t : tets) t = {pick(rng), pick(rng), pick(rng), pick(rng)};
  tets[0] = {3, 7, 1, 2};
  tets[1] = {5, 5, 5, 5};

  const std::size_t n = tets.size();
  std::vector<double> stretch_values(n), jacobian(n), lo(n), hi(n), volume(n);
  compute_tet_quality(points, tets, stretch_values.data(), jacobian.data(), lo.data(),
                      hi.data(), volume.data());
  std::vector<double> stretch_only(n);
  compute_tet_quality(points, tets, stretch_only.data(), nullptr, nullptr, nullptr, nullptr);
  std::vector<double> max_only(n);
  compute_tet_quality(points, tets, nullptr, nullptr, nullptr, max_only.data(), nullptr);

  for (std::size_t t = 0; t < n; ++t) {
    const Vec3 x[4] = {points[tets[t][0]], points[tets[t][1]], points[tets[t][2]],
                       points[tets[t][3]]};
    const DihedralRange r = tet_dihedral_range(x[0], x[1], x[2], x[3]);
    EXPECT_NEAR(stretch_values[t], tet_stretch(x[0], x[1], x[2], x[3]), 1e-14) << t;
    EXPECT_NEAR(jacobian[t], min_scaled_jacobian(CellKind::Tetra, x), 1e-14) << t;
    EXPECT_NEAR(lo[t], r.min, 1e-14) << t;
    EXPECT_NEAR(hi[t], r.max, 1e-14) << t;
    EXPECT_NEAR(volume[t], tet_signed_volume(x[0], x[1], x[2], x[3]), 1e-14) << t;
    EXPECT_EQ(stretch_only[t], stretch_values[t]) << t;
    EXPECT_EQ(max_only[t], hi[t]) << t;
  }
  EXPECT_EQ(stretch_values[1], 0.0);
  EXPECT_EQ(jacobian[0], 0.0);
}

// No tets: nothing is written, whether points are given or not, and null
// outputs are fine. Control: the same buffers with one tet get its values in
// slot 0 and nothing beyond it.
TEST(ComputeTetQuality, EmptyMesh) {
  compute_tet_quality({}, {}, nullptr, nullptr, nullptr, nullptr, nullptr);

  constexpr double kUntouched = -12345.0;
  std::array<std::array<double, 2>, 5> out;
  const auto fill = [&] {
    for (auto& measure : out) measure.fill(kUntouched);
  };
  const auto run = [&out](const std::vector<Vec3>& points, const std::vector<Tet>& tets) {
    compute_tet_quality(points, tets, out[0].data(), out[1].data(), out[2].data(), out[3].data(), out[4].data());
  };
  const TetPoints p = corner_tet();
  const std::vector<Vec3> points(p.begin(), p.end());
  for (const std::vector<Vec3>& given : {std::vector<Vec3>{}, points}) {
    fill();
    run(given, {});
    for (const auto& measure : out) {
      EXPECT_EQ(measure[0], kUntouched);
      EXPECT_EQ(measure[1], kUntouched);
    }
  }

  fill();
  run(points, {{0, 1, 2, 3}});
  const DihedralRange r = dihedral(p);
  EXPECT_DOUBLE_EQ(out[0][0], stretch(p));
  EXPECT_DOUBLE_EQ(out[1][0], min_scaled_jacobian(CellKind::Tetra, p.data()));
  EXPECT_DOUBLE_EQ(out[2][0], r.min);
  EXPECT_DOUBLE_EQ(out[3][0], r.max);
  EXPECT_DOUBLE_EQ(out[4][0], tet_signed_volume(p[0], p[1], p[2], p[3]));
  EXPECT_NEAR(out[4][0], 1.0 / 6.0, 1e-15);
  for (const auto& measure : out) EXPECT_EQ(measure[1], kUntouched);
}

}  // namespace
}  // namespace femorph
