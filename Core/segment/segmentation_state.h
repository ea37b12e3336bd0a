// Working state shared by the steps of segment_surface (thesis 2.4, A11-A16).
// Internal to Core/segment.
#pragma once

#include "common/stamps.h"
#include "geometry/fit_primitives.h"
#include "segment/detect_sharp_edges.h"
#include "segment/normal_tensor_curvature.h"
#include "segment/segmentation.h"

#include <vector>

namespace femorph {
namespace segment {

/// A region while it is being extracted.
struct WorkRegion {
  SurfaceType type = SurfaceType::Unknown;
  SurfacePrimitive surface;
  std::vector<index_t> triangles;
  double fit_rms = 0, fit_max = 0;
  bool alive = true;
};

struct State {
  const SurfaceMesh& surface;
  const SegmentationParams& params;
  SharpEdges sharp;
  Curvature curvature;
  /// Per triangle: index into regions, or -1 while unassigned.
  std::vector<index_t> triangle_region;
  std::vector<WorkRegion> regions;
  /// Absolute distance under which a vertex inside a face lies on its
  /// fitted surface (the tight tolerance).
  double tolerance = 0;
  /// Absolute distance under which a vertex on a face's boundary curves lies
  /// on it: CAD systems store edge curves as approximations of the face
  /// intersections, so mesh nodes on them lie off the faces by far more
  /// than the nodes inside (0 until measured by extract_planar_regions;
  /// near_tolerance() is never below the tight one).
  double curve_tolerance = 0;
  /// Distance under which a vertex lies on a surface to the mesh's own
  /// precision (1e4 x noise, at least 1e-6 of the part; 0 until measured by
  /// extract_planar_regions, and with adaptive_tolerance off, when the
  /// tolerance is what the user set): where the boundary curves are approximate the
  /// tolerance stays above it (see measure_precision), and this tells the
  /// vertices inside a face from those merely near it.
  double precision = 0;
  /// A length of the part (bounding box diagonal), for relative comparisons.
  double scale = 1;
  /// The mesh's noise: median distance of the planar seeds' inner vertices
  /// to their planes (0 until measured by extract_planar_regions).
  double noise = 0;
  std::vector<std::string> warnings;

  State(const SurfaceMesh& s, const SegmentationParams& p) : surface(s), params(p) {}

 private:
  // Marks for vertices_of: linear time, no sort (it runs on every fit).
  struct Scratch {
    Stamps<std::uint32_t> vertex_marks;
    std::vector<index_t> vertex_slot;
    Stamps<std::uint32_t> triangle_marks;
  };
  mutable Scratch scratch_;
  /// scratch_ on the calling thread; a thread's own inside a parallel loop,
  /// so that the const queries (fits, vertices_of) may run concurrently.
  Scratch& scratch() const;

 public:

  /// Distinct vertices of a triangle set, in order of first appearance.
  /// After the call, slot(v) is v's position in the result (until the next).
  std::vector<index_t> vertices_of(const std::vector<index_t>& triangles) const;
  index_t slot(index_t v) const { return scratch().vertex_slot[v]; }
  /// The tolerance of boundary-curve vertices.
  double near_tolerance() const { return std::max(tolerance, curve_tolerance); }
  /// The tolerance of a vertex exactly on a surface: precision, never above
  /// the tight tolerance (the tight tolerance while unmeasured).
  double exact_tolerance() const { return precision > 0 ? std::min(precision, tolerance) : tolerance; }
  /// Per vertex of `vertices` (= vertices_of(triangles)): 1 when every mesh
  /// triangle around it is in `triangles`, i.e. it is inside the set, not on
  /// its border (where a face's boundary curves run).
  std::vector<char> inner_mask(const std::vector<index_t>& triangles, const std::vector<index_t>& vertices) const;
  /// The vertices a fit of `triangles` uses: the inner ones when there are
  /// enough of them (at least `min_count` and a quarter of all), else all.
  /// Inner vertices of a CAD mesh lie on their face exactly; its border
  /// vertices only to the accuracy of the file's edge curves.
  std::vector<index_t> fit_vertices(const std::vector<index_t>& triangles, std::size_t min_count) const;
  /// The vertices of `triangles` within the tight tolerance of s (the exact
  /// ones), or all of them when fewer than `min_count` are.
  std::vector<index_t> exact_vertices(const SurfacePrimitive& s, const std::vector<index_t>& triangles,
                                      std::size_t min_count) const;
  /// Largest distance to s of the vertices of `triangles`, the border ones
  /// (see inner_mask) counted in units of the curve tolerance: comparable with
  /// the tight tolerance for both kinds. The plain largest distance while the
  /// curve tolerance is not above the tight one.
  double scaled_max_distance(const SurfacePrimitive& s, const std::vector<index_t>& triangles) const;
  /// Positions (and vertex normals) of vertices.
  std::vector<Vec3> positions(const std::vector<index_t>& vertices) const;
  std::vector<Vec3> normals(const std::vector<index_t>& vertices) const;
  /// Largest distance of a triangle's vertices to a surface.
  double triangle_distance(const SurfacePrimitive& s, index_t triangle) const;
  /// Largest distance to s of the triangle's vertices that no triangle of
  /// region `other` touches (all of them if every one is touched): how well s
  /// explains the triangle away from its border with `other`. The plain
  /// triangle_distance while the curve tolerance is not above the tight one.
  double triangle_distance_off(const SurfacePrimitive& s, index_t triangle, index_t other) const;
  /// Whether the triangle lies on s with the tight tolerance: its vertices
  /// within it and its normal agreeing with the surface normal (same side,
  /// within 30 degrees).
  bool triangle_on(const SurfacePrimitive& s, index_t triangle) const;
  /// Whether the triangle lies on s allowing for approximate boundary
  /// curves: its vertices within near_tolerance(), at least one of them
  /// within the tight tolerance (a vertex inside the face: a neighbouring
  /// face meeting at a small angle is not taken beyond one triangle) unless
  /// all three lie on sharp edges (a face one triangle wide), and
  /// its normal agreeing as for triangle_on. The same as triangle_on while
  /// the curve tolerance is not above the tight one.
  bool triangle_near(const SurfacePrimitive& s, index_t triangle) const;
  /// Region `from`'s triangles into region `into` when every one of them
  /// lies near into's surface (triangle_near); `from` is then empty and dead.
  /// True when they moved.
  bool absorb_if_near(index_t from, index_t into);
  /// Unit normal at a vertex: the curvature's when valid, else the
  /// area-weighted mean of its triangles' normals.
  Vec3 vertex_normal(index_t v) const;
};

/// Fits a surface of `type` to the vertices of `triangles` (the type's direct
/// fit, RANSAC for cones/spheres/tori, then LM). ok = false if no fit.
/// `refine` = false skips the final LM (for quick verdicts).
FitResult fit_region(const State& state, SurfaceType type, const std::vector<index_t>& triangles,
                     const std::vector<Vec3>* max_dirs = nullptr, bool refine = true);

/// Refits a region's surface of `type` from `start` (least squares for a
/// plane, LM for the others) over fit_vertices, or over all its vertices when
/// that fit misses a border vertex by more than the curve tolerance (the
/// inner vertices of a narrow strip, along one line, leave the fit free
/// across it). max_abs as scaled_max_distance.
FitResult refit_region(const State& state, SurfaceType type, const SurfacePrimitive& start,
                       const std::vector<index_t>& triangles);

/// Region integration, thesis 2.4.3.3: starting from `seed` triangles and a
/// fit of `type`, alternately grows the region over unassigned triangles
/// lying on the fitted surface (region growing by distance) and refits,
/// until nothing changes. Returns the grown region (not yet registered in
/// state.triangle_region); an empty region if the seed does not fit.
WorkRegion integrate_region(const State& state, SurfaceType type, const std::vector<index_t>& seed,
                            const FitResult& initial);

/// Whether a fit is a plausible CAD surface for these triangles rather than a
/// fit of noise (beyond the thesis): cones between 1 deg and the maximum
/// half angle with the apex near the part, tori with R > 0 (ring, horn and
/// spindle: a spindle torus's outer part rounds a boss end), and curvature
/// that shows over the region (the sagitta e^2 / (8 rho) over the region's
/// extent e exceeds the tolerance; otherwise a plane would do).
bool plausible_fit(const State& state, const SurfacePrimitive& surface, const std::vector<index_t>& triangles);

/// Minimum number of distinct vertices for a fit of `type` to mean anything
/// (more than its parameters).
std::size_t min_vertices(SurfaceType type);

/// Whether a simpler type fits the triangles within the tolerance, or nearly
/// as well as the fit of `type` whose largest distance is `max_abs` (within
/// three times it): then a cone or torus is fitting noise rather than a
/// cylinder or sphere, a curved fit rather than a plane (meshes whose nodes
/// are not exactly on their CAD surfaces). On exact CAD meshes max_abs is
/// ~1e-15 and only the tolerance counts.
bool simpler_type_fits(const State& state, SurfaceType type, const std::vector<index_t>& triangles, double max_abs);

/// Tries each type on `triangles` (unassigned), simplest first; registers the
/// first whose fit every triangle lies on (integrate_region also refuses
/// implausible fits and those a simpler type nearly matches) and returns
/// true; false if none fits.
bool fit_patch(State& state, const std::vector<index_t>& triangles);

/// Registers a region: assigns its triangles. Returns its index.
index_t add_region(State& state, WorkRegion region);

/// Connected components (through shared edges, not crossing sharp edges when
/// `stop_at_sharp`) of the triangles for which `member` is true.
template <class Member>
std::vector<std::vector<index_t>> connected_components(const State& state, bool stop_at_sharp, Member member);

// The steps, one file each.
void extract_planar_regions(State& state);       // A13, planes
void extract_cylindrical_regions(State& state);  // A13, cylinders (with the cone check)
void extract_conical_regions(State& state);      // A13, cones (RANSAC over seed regions)
void extract_spherical_regions(State& state);    // A13, spheres
void extract_torus_regions(State& state);        // A14, with the false-region merges and torus -> sphere
void classify_remaining_regions(State& state);   // beyond the thesis: leftovers get the best-fitting primitive or unknown
void reestimate_region_boundaries(State& state); // A14 boundary re-estimation, applied to every region border
void merge_equal_regions(State& state);          // adjacent regions with one surface become one
/// Fitted regions take back the unknown triangles that lie on their surface
/// (a fragment cut out of a real face), growing over them breadth-first.
void absorb_unknown_triangles(State& state);
bool dissolve_ambiguous_regions(State& state);   // freeform faces: patchworks of local fits become unknown; true if any
void absorb_fragment_regions(State& state);      // A14 false regions, where curves are approximate: fragments join a neighbour
void refine_region_fits(State& state);           // A15, Levenberg-Marquardt
void build_region_graph(const State& state, Segmentation& out);          // adjacency, G0/G1, convexity
void recognize_boundary_curves(const State& state, Segmentation& out);  // A16

}  // namespace segment
}  // namespace femorph

#include "segment/segmentation_state_impl.h"
