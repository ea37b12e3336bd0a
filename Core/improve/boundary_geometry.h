// The fitted surfaces and curves the boundary vertices of an improved mesh
// must stay on (thesis 2.6.1.3: "the new vertex is moved onto the fitted
// surface"; 2.6.5: vertices on curved regions move in the parameter space of
// their surface or curve). Built from the segmentation (Core/segment); the
// constraint of a vertex is found from the mesh itself (the regions of its
// boundary faces), so it stays right after splits and collapses.
#pragma once

#include "common/types.h"
#include "geometry/curve_primitive.h"
#include "geometry/discrete_surface.h"
#include "geometry/surface_primitive.h"

#include <array>
#include <vector>

namespace femorph {

class TetMesh;
struct BoundaryCurve;

struct BoundaryGeometry {
  /// Fitted surface per region id (the ids of TetMesh::face_region). Type
  /// Unknown (or a region id past the end): not fitted, its vertices stay.
  std::vector<SurfacePrimitive> regions;
  /// Fitted boundary curves and the two regions each separates.
  std::vector<CurvePrimitive> curves;
  std::vector<std::array<index_t, 2>> curve_regions;
  /// Per region id: the triangles of a region without a fit, as given
  /// (add_discrete_regions); its surface vertices move on them. Empty
  /// entries (or none at all): those vertices stay.
  std::vector<DiscreteSurface> discrete;

  const SurfacePrimitive* region(index_t r) const {
    return r >= 0 && r < static_cast<index_t>(regions.size()) && regions[r].type != SurfaceType::Unknown
               ? &regions[r]
               : nullptr;
  }
  const DiscreteSurface* discrete_region(index_t r) const {
    return r >= 0 && r < static_cast<index_t>(discrete.size()) && !discrete[r].empty() ? &discrete[r] : nullptr;
  }
};

/// The geometry of a segmentation as FEMorph Segment's arrays carry it: the
/// fitted surface of each region (type Unknown: none) and each boundary
/// curve's fit with the two regions it separates (thesis 2.5.1.1).
BoundaryGeometry make_boundary_geometry(const std::vector<SurfacePrimitive>& regions,
                                        const std::vector<BoundaryCurve>& curves);

/// Keeps the current boundary triangles of every region without a fit (and
/// of faces without a region: none) as geometry.discrete, so that its
/// surface vertices can move on them (beyond the thesis: a stretched fillet
/// is no torus any more, and its frozen triangles would bound the quality).
void add_discrete_regions(const TetMesh& mesh, BoundaryGeometry& geometry);

/// Where a boundary vertex may go.
struct VertexConstraint {
  enum Kind : std::uint8_t {
    Free,     ///< inner vertex
    Surface,  ///< on one fitted region: `surface`
    Curve,    ///< on a curve between regions a and b: `curve` (may be null)
              ///< and the two surfaces
    Fixed,    ///< a corner, or a region or curve without a fit (nor
              ///< triangles kept for it)
    Discrete,  ///< on one region without a fit: on its kept triangles
  };
  Kind kind = Free;
  index_t region_a = kInvalidIndex, region_b = kInvalidIndex;
  const SurfacePrimitive* surface = nullptr;    ///< Surface: its region; Curve: region a
  const SurfacePrimitive* surface_b = nullptr;  ///< Curve: region b
  const CurvePrimitive* curve = nullptr;        ///< Curve: the fitted curve, when one is known
  const DiscreteSurface* discrete = nullptr;    ///< Discrete: the region's triangles
};

/// The constraint of vertex v from the regions of its boundary faces and its
/// class: Inner -> Free; one region -> Surface (Discrete when the region has
/// no fit but kept triangles, else Fixed); two regions -> Curve (Fixed when either region has no fit and no
/// line or circle curve between them is known); Corner or more -> Fixed.
/// Among several curves between the same two regions the one closest to v.
/// Safe to call from several threads at once (it walks v's ball with
/// per-thread marks).
VertexConstraint vertex_constraint(const TetMesh& mesh, const BoundaryGeometry& geometry, index_t v);
/// The same from v's ball (TetMesh::vertex_ball), for a caller that has it:
/// no walk, and no use of the mesh's shared walk marks (so callers may run
/// in parallel).
VertexConstraint vertex_constraint(const TetMesh& mesh, const BoundaryGeometry& geometry, index_t v,
                                   const std::vector<index_t>& ball);

/// Closest point to p that satisfies c: the surface's (or kept triangles')
/// closest point; on a
/// line or circle (arc) the curve's; on other curves alternating projections
/// onto the two surfaces (converging to their intersection); Fixed: nullptr
/// result (returns false); Free: p.
bool project_to_constraint(const VertexConstraint& c, const Vec3& p, Vec3* out);

/// Distance from p to the constraint (0 for Free, NaN for Fixed).
double constraint_distance(const VertexConstraint& c, const Vec3& p);

/// Closest point of a line or circle / circular arc (as a full circle); other
/// curve types: p unchanged, returns false.
bool closest_point_on_curve(const CurvePrimitive& curve, const Vec3& p, Vec3* out);

}  // namespace femorph
