// Segmentation of a closed surface into planar, cylindrical, conical,
// spherical, toroidal and unknown regions with their boundary curves,
// thesis 2.4 (A11-A16), and the surface and boundary information of 2.5.1.1.
#pragma once

#include "geometry/curve_primitive.h"
#include "geometry/surface_primitive.h"
#include "mesh/surface_mesh.h"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace femorph {

/// Properties with their thesis defaults (2.4.3.2, 2.4.3.3).
struct SegmentationParams {
  /// A11: an edge is sharp when its triangles' normals differ by more (deg).
  double sharp_angle_deg = 30.0;
  /// A13 seeds: planar vertices have normal directions within this (deg).
  double plane_angle_tolerance_deg = 1.0;
  /// A13 seeds: neighbouring minimum-curvature directions within this on a
  /// cylinder (thesis 1.0-1.5 deg) and on a cone (0.4-0.8 deg).
  double cylinder_angle_tolerance_deg = 1.5;
  double cone_angle_tolerance_deg = 0.8;
  /// A13 seeds: a triangle whose vertices' principal directions differ by
  /// more than this is a sphere seed (thesis: 60 deg).
  double sphere_direction_angle_deg = 60.0;
  /// The tolerance of vertices inside a face: such a vertex lies on a fitted
  /// surface when closer than this times the mean edge length; the largest
  /// tolerance used (adaptive_tolerance may lower it). Meshes whose nodes are
  /// not exactly on the CAD surfaces (remeshed, exported with few digits)
  /// need more, e.g. 0.05. Vertices on boundary curves have their own
  /// tolerance, measured (6 x the 0.9-quantile of the planar seeds' border
  /// vertex distances, at most 1e-3 of the part; never below this one).
  double distance_tolerance = 1e-2;
  /// Lower the distance tolerance to the mesh's own precision, measured on
  /// its planar faces: on a mesh whose nodes lie on the CAD surfaces to 1e-14,
  /// the tolerance becomes max(1e4 x that, 1e-6 of the part) if smaller.
  /// Region boundaries then hold even where faces meet at a fraction of a
  /// degree. Turn off for meshes whose planes are exact but whose curved
  /// faces are not (a faceted or remeshed part).
  bool adaptive_tolerance = true;
  /// RANSAC (cones, spheres, tori): iterations and seed (deterministic).
  int ransac_iterations = 500;
  std::uint64_t random_seed = 1;
  /// A15: Levenberg-Marquardt refinement of every curved region's fit.
  bool refine_fits = true;
  /// Cones wider than this are rejected (thesis 2.4.3.3 step 6, deg).
  double max_cone_half_angle_deg = 80.0;
};

enum class Convexity : std::int32_t { NotApplicable = 0, Convex = 1, Concave = 2 };
enum class Continuity : std::int32_t { G0 = 0, G1 = 1 };

struct Region {
  index_t id = kInvalidIndex;
  SurfaceType type = SurfaceType::Unknown;
  SurfacePrimitive surface;    // fitted (type Unknown: nothing fitted)
  double fit_rms = 0;          // over the region's vertices
  double fit_max = 0;
  double area = 0;
  index_t triangle_count = 0;
  /// Curved regions: convex (material inside the curvature, a boss) or
  /// concave (a hole, a fillet in a corner); torus: whether the core circle is
  /// outside the part (concave) or inside (convex). Planes: NotApplicable.
  Convexity convexity = Convexity::NotApplicable;
  std::vector<index_t> neighbors;         // adjacent regions, ascending
  std::vector<Continuity> continuity;     // per neighbour: G1 when tangent along the shared curve
  std::vector<index_t> curves;            // boundary curves of the region
};

struct BoundaryCurve {
  index_t id = kInvalidIndex;
  CurveType type = CurveType::Unclassified;
  CurvePrimitive curve;
  double fit_max = 0;
  std::vector<index_t> vertices;   // surface vertices in order (a loop does not repeat the first)
  bool closed = false;
  index_t region_a = kInvalidIndex, region_b = kInvalidIndex;
  Continuity continuity = Continuity::G0;
};

/// Wall time of each step, seconds (thesis Table 2.9).
struct SegmentationTimes {
  double sharp_edges = 0, curvature = 0, planes = 0, cylinders = 0, cones = 0, spheres = 0, tori = 0,
         remaining = 0,  // beyond the thesis: fits of what no seed reached
         cleanup = 0,    // merges, boundary re-estimation, dissolving local fits
         refinement = 0, curves = 0, total = 0;
};

struct Segmentation {
  std::vector<index_t> triangle_region;   // per surface triangle
  std::vector<Region> regions;
  std::vector<BoundaryCurve> curves;
  /// Per surface vertex: 1 surface, 2 curve ("boundary edge vertex"), 3 corner
  /// ("feature vertex"), as VertexClass; and the curve it lies on (-1).
  std::vector<std::int8_t> vertex_class;
  std::vector<index_t> vertex_curve;
  SegmentationTimes times;
  std::vector<std::string> warnings;      // e.g. regions left unknown, fits that did not converge
};

/// Progress in [0, 1] and the name of the step; return false to abort.
using SegmentationProgress = std::function<bool(double fraction, const char* step)>;

/// Runs A11-A16 on a closed surface. Fails with a message on an aborted run
/// or a surface it cannot work on (e.g. no triangles).
Status segment_surface(const SurfaceMesh& surface, const SegmentationParams& params, Segmentation& out,
                       const SegmentationProgress& progress = {});

class TetMesh;

/// Boundary points closer than this times the mean edge length to another
/// boundary point are duplicate nodes (segment_boundary's warning).
constexpr double kCoincidentPointTolerance = 1e-6;

/// The boundary of a tet mesh (extract_boundary_surface) segmented by
/// segment_surface into `out`; `surface` receives the boundary with its
/// source vertices and faces. Fails with a message naming the problem (an
/// open or non-manifold boundary with its counts, or the segmentation's).
/// Degenerate boundary triangles are a warning in out.warnings, first; so
/// are boundary points that coincide with other boundary points (within
/// kCoincidentPointTolerance times the mean edge length: an unmerged seam),
/// with their count and what to do (merge them first).
/// Progress: the extraction at 0, then segment_surface's.
Status segment_boundary(const TetMesh& mesh, const SegmentationParams& params, SurfaceMesh& surface,
                        Segmentation& out, const SegmentationProgress& progress = {});

/// Fixed-width rows of the RegionParameters field array (docs/ARCHITECTURE.md),
/// one per region, so Improve (and Deform) read the fits Segment wrote:
///   0-2 point, 3-5 axis, 6 radius, 7 minor_radius, 8 half_angle (rad),
///   9 convexity (Convexity), 10 fit_rms, 11 area
constexpr int kRegionParameterWidth = 12;
std::array<double, kRegionParameterWidth> pack_region_parameters(const Region& region);
/// Inverse of pack_region_parameters for the surface (type given separately).
SurfacePrimitive unpack_region_surface(SurfaceType type, const double* row);

/// Fixed-width rows of the CurveParameters field array, one per curve:
///   0-2 center, 3-5 normal, 6-8 direction, 9 radius, 10 minor_radius,
///   11-13 start, 14-16 end, 17 region_a, 18 region_b, 19 continuity
constexpr int kCurveParameterWidth = 20;
std::array<double, kCurveParameterWidth> pack_curve_parameters(const BoundaryCurve& curve);
/// Inverse of pack_curve_parameters: the curve's fit, its two regions and
/// continuity (type given separately; id, vertices and closed are not in the
/// row). Region ids are rounded to the nearest integer; the caller checks
/// them.
BoundaryCurve unpack_curve_parameters(CurveType type, const double* row);

}  // namespace femorph
