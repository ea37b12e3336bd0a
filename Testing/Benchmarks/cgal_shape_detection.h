// The peer of FEMorph Segment in the benchmark: CGAL's Efficient RANSAC shape
// detection (Schnabel, Wahl and Klein 2007; CGAL's Shape_detection package) on
// the boundary vertices of a tet mesh and their normals.
//
// Only the benchmarks use it (Debian libcgal-dev, header-only; CGAL's kernel
// needs libgmp-dev and libmpfr-dev). The interface is plain std:: types so the
// caller needs neither CGAL nor FEMorph's core; CGAL stays inside the .cpp.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace femorph {
namespace bench {

// Parameters of CGAL's Efficient_RANSAC::Parameters, given relative to the
// input so that one set fits parts of any size. CGAL's manual ("Shape
// Detection", section Parameters) documents the absolute values:
//   probability       probability that the best candidate was missed; lower
//                     searches longer and is more reliable (manual default 0.05;
//                     CGAL 5.5's Parameters() constructor sets 0.01).
//   min_points        smallest shape in points (default 1% of the points).
//   epsilon           largest point-to-shape distance (default 1% of the
//                     bounding box diagonal).
//   cluster_epsilon   largest distance between neighbouring points of one
//                     shape, the cell size of the connected-component bitmap
//                     (default 1% of the bounding box diagonal). It must exceed
//                     the point spacing, or large coarse faces fall apart.
//   normal_threshold  smallest cosine between point normal and shape normal
//                     (default 0.9, about 25 degrees).
// Our defaults differ where the input differs from a scanned point cloud:
// points lie on the CAD surfaces exactly and their normals inside faces are
// accurate (epsilon and the normal angle small), but they are spaced like a
// graded FE mesh, up to several percent of the diagonal on large planes
// (cluster_epsilon larger), and fillets hold well under 1% of the points
// (min_points smaller). Chosen by a sweep on the five Data/ parts, five seeds
// each (bench_cgal_peer): these defaults recover about twice as many CAD
// faces as CGAL-like ones (epsilon 0.002, normal_threshold 0.9).
// cluster_epsilon 0.03-0.1, min_points 0.001-0.005, probability 0.01 and
// normal thresholds 0.98-0.998 change little (a lower probability costs
// much more time).
struct CgalRansacParameters {
  double probability = 0.05;
  double min_points_fraction = 0.002;  // of the number of points ...
  std::size_t min_points_at_least = 10;  // ... but at least this many
  double epsilon_relative = 0.0005;      // of the bounding box diagonal
  double cluster_epsilon_relative = 0.05;  // of the bounding box diagonal
  double normal_threshold = 0.99;  // about 8 degrees
  // Cylinder and sphere candidates with a radius above this (relative to the
  // bounding box diagonal; 0: no limit) or below epsilon are rejected: CGAL
  // 5.5 crashes on such degenerate candidates (see the .cpp).
  double max_radius_relative = 1.0;
  bool planes = true;
  bool cylinders = true;
  bool cones = true;
  bool spheres = true;
  bool tori = true;
  // CGAL draws samples from CGAL::get_default_random(), which is seeded with
  // the time; the function reseeds it (in the calling thread) with this
  // value so that runs repeat. 0 leaves CGAL's generator alone.
  unsigned int seed = 1;
};

enum class CgalShapeType { Plane = 0, Cylinder = 1, Cone = 2, Sphere = 3, Torus = 4 };
constexpr int kCgalShapeTypeCount = 5;
const char* cgal_shape_type_name(CgalShapeType type);  // "plane", "cylinder", ...

// One detected shape. Fields that do not apply to the type are NaN.
struct CgalShape {
  CgalShapeType type = CgalShapeType::Plane;
  std::array<double, 3> normal;  // plane: unit normal n, with n.x = offset
  double offset;                 //   (CGAL's plane a x + b y + c z + d = 0: offset = -d)
  std::array<double, 3> axis;    // cylinder, cone (from the apex into the cone), torus: unit
  std::array<double, 3> point;   // cylinder: a point on the axis; cone: the apex;
                                 //   sphere, torus: the centre
  double radius;                 // cylinder, sphere
  double half_angle_deg;         // cone
  double major_radius;           // torus
  double minor_radius;           // torus
  std::vector<std::size_t> indices;  // input points assigned to this shape (indices into the
                                     // caller's arrays; CGAL's own refer to its reordered copy)
};

struct CgalShapeDetectionResult {
  bool ok = false;
  std::string message;  // why not, when !ok
  double seconds = 0;             // the whole call: copy in, octrees, detection, copy out
  double preprocess_seconds = 0;  // CGAL's preprocess(): the octrees
  double detect_seconds = 0;      // CGAL's detect()
  // The absolute parameters used.
  double bbox_diagonal = 0;
  double epsilon = 0;
  double cluster_epsilon = 0;
  std::size_t min_points = 0;
  double max_radius = 0;  // infinity when unlimited
  std::array<std::size_t, kCgalShapeTypeCount> count_by_type{};  // index: CgalShapeType
  std::size_t unassigned_points = 0;
  std::vector<CgalShape> shapes;
};

// Runs Efficient RANSAC with the shape types enabled in `parameters` on points
// and their unit normals (same size; normals pointing outwards or not: CGAL
// does not use the orientation). Single-threaded (CGAL's implementation is).
CgalShapeDetectionResult cgal_efficient_ransac(const std::vector<std::array<double, 3>>& points,
                                               const std::vector<std::array<double, 3>>& normals,
                                               const CgalRansacParameters& parameters = {});

}  // namespace bench
}  // namespace femorph
