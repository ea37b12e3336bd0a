// Fitting analytic surfaces to points on a mesh region (thesis 2.4.3.3,
// 2.4.4, 2.4.5). Every fit reports its residuals; deterministic (RANSAC
// takes a seed).
#pragma once

#include "geometry/surface_primitive.h"

#include <cstdint>
#include <vector>

namespace femorph {

/// A fitted surface and how well it fits the points it was fitted to.
struct FitResult {
  SurfacePrimitive surface;
  double rms = 0;       // root mean square of signed_distance over the points
  double max_abs = 0;   // largest |signed_distance|
  int iterations = 0;   // RANSAC or LM iterations used
  int inlier_count = 0; // RANSAC: points within inlier_tolerance (others: all the points)
  bool ok = false;      // false: too few points, degenerate input, no model found
};

/// Residuals (rms, max) of `surface` over `points`, as in FitResult.
FitResult evaluate_fit(const SurfacePrimitive& surface, const std::vector<Vec3>& points);

/// Plane by least squares (thesis: average normal and barycentre; here the
/// total least squares plane, whose normal is oriented like the mean of
/// `normals` when given). At least 3 points.
FitResult fit_plane(const std::vector<Vec3>& points, const std::vector<Vec3>* normals = nullptr);

/// Cylinder, thesis Fig. 2.9: the axis is the normal of the plane fitted to
/// the unit normals mapped onto the Gaussian sphere (through its centre, as a
/// cylinder's is: well determined on narrow strips too); points projected
/// along the axis get a least-squares circle (fit_circle_2d). At least 5
/// points with normals (either sign); refused when all normals are parallel.
FitResult fit_cylinder(const std::vector<Vec3>& points, const std::vector<Vec3>& normals);

/// The cylinder-or-cone test of 2.4.3.3: distance from the Gaussian sphere's
/// centre to the plane fitted to the unit normals (0 for a cylinder, sin of
/// the cone's half angle for a cone: its normals make the angle pi/2 + half
/// angle with the axis). NaN for fewer than 3 normals or when they are all
/// parallel (no plane).
double gaussian_sphere_plane_offset(const std::vector<Vec3>& normals);

/// A circle in the plane (also used for a cylinder's section, a torus's
/// meridian and boundary curves).
struct Circle2dFit {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0;
  double rms = 0;      // of the geometric distances |p - center| - radius
  double max_abs = 0;
  bool ok = false;     // false: fewer than 3 points, collinear points
};

/// Least-squares circle: the algebraic fit (Kasa) on centred, scaled points,
/// then Gauss-Newton on the geometric distances (exact points: exact circle;
/// noisy points: no algebraic bias).
Circle2dFit fit_circle_2d(const std::vector<Eigen::Vector2d>& points);

/// Sphere by linear least squares (algebraic), then geometric refinement is
/// left to refine_fit_lm. At least 4 points.
FitResult fit_sphere(const std::vector<Vec3>& points);

struct RansacParams {
  int iterations = 500;
  double inlier_tolerance = 1e-3;        // absolute distance
  double max_cone_half_angle = 1.3963;   // 80 degrees (thesis 2.4.3.3 step 6)
  std::uint64_t seed = 1;
};

/// RANSAC fits (below) work on the points centred and scaled to unit size;
/// inlier_tolerance stays an absolute distance. Beyond the thesis each also
/// scores a model fitted to all the points (a clean region needs no lucky
/// sample), and every new best model is refitted to its consensus set while
/// that improves the consensus (LO-RANSAC; spheres: linear least squares;
/// cones, tori: from the normals of the inliers whose normal agrees with the
/// model's within 20 degrees; LM is refine_fit_lm's). Candidates are scored
/// on a random subset of 200 points first. rms and max_abs are over all the
/// points, inlier_count is the consensus; iterations the samples drawn
/// (fewer than params.iterations once a better consensus has probability
/// < 1e-6, after at least 50). Normals need not be unit; their sign does not
/// matter. The fits only start refine_fit_lm: with normals from a mesh (off
/// by a degree or more) a loose inlier_tolerance (a few % of the smallest
/// radius, a fraction of an edge length) works far better than the tight
/// tolerance of region growing.

/// Cone by RANSAC, thesis Fig. 2.10: apex from three tangent planes, axis
/// from the unit vectors apex -> points, opening angle Eq. 2.7; consensus by
/// inlier count. Cones wider than max_cone_half_angle are rejected. At least
/// 6 points. The all-points model: axis normal to the plane of the normals on
/// the Gaussian sphere, apex where all tangent planes meet.
FitResult ransac_cone(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const RansacParams& params);

/// Sphere by RANSAC, thesis Fig. 2.11: centre where the three normal lines
/// meet (least squares), radius the mean distance. At least 4 points.
FitResult ransac_sphere(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const RansacParams& params);

/// Torus by RANSAC, thesis Fig. 2.14: axis from the planes spanned by the
/// normal and the principal direction of maximum curvature at three points
/// (`max_dirs`), meridian circle through the three points rotated into one
/// plane. Beyond the thesis: when `max_dirs` is null, the axis comes from the
/// normals alone (lines x + t n of a torus all meet its axis): the line
/// meeting them best in Plücker coordinates, from samples of 5 points, and
/// from all the points as the first candidate (also when `max_dirs` is
/// given), then the meridian circle of the points. At least 7 points.
FitResult ransac_torus(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                       const std::vector<Vec3>* max_dirs, const RansacParams& params);

struct LmParams {
  int max_iterations = 200;
  double tolerance = 1e-15;   // stop when the relative decrease of J falls below
};

/// Levenberg-Marquardt refinement, thesis 2.4.5 Eq. 2.8 with the control
/// variables and normalisations of Fig. 2.16 (cone, sphere, torus; cylinder
/// and plane too): minimises the sum of squared geometric distances. Works on
/// the points centred and scaled to unit size (any units, any position);
/// analytic Jacobians, minimal increments per step (an axis turns by two
/// angles, an axis point moves across the axis), Fig. 2.15's damping.
/// Returns the refined surface with its residuals; the sum of squares never
/// increases. ok = false (then `surface` is `initial`, with its residuals) for
/// fewer points than parameters (plane 3, sphere 4, cylinder 5, cone 6,
/// torus 7), an invalid `initial` (type Unknown, zero axis, radius <= 0, cone
/// half angle outside (0, pi/2)), or a degenerate result.
FitResult refine_fit_lm(const SurfacePrimitive& initial, const std::vector<Vec3>& points, const LmParams& params = {});

}  // namespace femorph
