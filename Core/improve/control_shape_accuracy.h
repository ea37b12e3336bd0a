// Shape approximation accuracy control, thesis 2.6.4 (Fig. 2.41): the
// geometric error of a surface edge is the distance from its midpoint to the
// fitted surface of its curved region; edges whose error exceeds the
// region's acceptable error (the largest error of the region before the
// deformation) are split and the new vertex is moved onto the surface.
#pragma once

#include "common/types.h"
#include "improve/boundary_geometry.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femorph {

class TetMesh;

/// eps_S(e) per region id (Fig. 2.41 (a)): the largest distance from the
/// midpoint of a boundary edge of the region to its fitted surface. Only
/// curved regions (cylinder, cone, sphere, torus) have one; planes, unknown
/// regions and regions without edges get NaN. Edges on a curve between two
/// regions count for both.
std::vector<double> region_geometric_error(const TetMesh& mesh, const BoundaryGeometry& geometry);
/// The same from a tet list and its boundary face regions (per tet, the
/// region of the face opposite local vertex i, < 0 where interior): no
/// TetMesh to build, e.g. for a reference mesh read with its segmentation.
std::vector<double> region_geometric_error(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                                           const std::vector<Tet>& face_regions, const BoundaryGeometry& geometry);

/// Whether moving boundary vertex v to p keeps the chord error (2.6.4) of
/// its boundary edges on curved regions within `acceptable` (per region; NaN
/// or <= 0: not checked), or at least does not raise an edge that is
/// already beyond it. For smoothing steps: ODT on a curved surface makes
/// chords longer, and a split that would restore the accuracy can cost
/// quality.
bool chords_within_error(const TetMesh& mesh, const BoundaryGeometry& geometry, const std::vector<double>& acceptable,
                         index_t v, const Vec3& p);
/// The same with v's ball given (every live tet that holds v).
bool chords_within_error(const TetMesh& mesh, const BoundaryGeometry& geometry, const std::vector<double>& acceptable,
                         index_t v, const Vec3& p, const std::vector<index_t>& ball);
/// The same for the collapse of edge (keep, remove) with keep placed at x
/// (balls of both ends given): the boundary edges the surviving vertex will
/// have on curved regions stay within `acceptable`, or at least no worse than
/// the edge each replaces. Mesh density control (2.6.3) collapses boundary
/// edges; a chord it lengthens past the error may be one the accuracy
/// control cannot split again without a poor tet.
bool collapse_chords_within_error(const TetMesh& mesh, const BoundaryGeometry& geometry,
                                  const std::vector<double>& acceptable, index_t keep, index_t remove, const Vec3& x,
                                  const std::vector<index_t>& ball_keep, const std::vector<index_t>& ball_remove);

struct AccuracyControlOptions {
  /// Restriction to a region: only edges whose two vertices are flagged
  /// (vertices a split creates are flagged). Empty: every edge.
  std::vector<std::uint8_t> vertex_mask;
  /// Refuse a split that would make a tet with stretch below this (and below
  /// the worst tet it replaces).
  double min_stretch = 0.05;
  /// Safety bound on splits; 0: 4 per boundary edge over the limit + 100.
  std::size_t max_splits = 0;
  /// When set: every vertex whose position or neighbours an accepted split
  /// changed is set to 1 (the vector grows as needed).
  std::vector<char>* touched = nullptr;
};

struct AccuracyControlStats {
  std::size_t edges_over = 0;  ///< edges above the acceptable error at the start
  std::size_t splits = 0;
  std::size_t refused = 0;     ///< split or projection refused (edge left)
};

/// Thesis 2.6.4 (Fig. 2.41 (b)): splits the boundary edges of curved regions
/// whose geometric error exceeds `acceptable[region]` (NaN or <= 0: region
/// skipped), worst first, moving each new vertex onto the fitted surface (or
/// curve, for an edge on a boundary curve) with vertex_constraint(). A split
/// whose vertex cannot be put on the surface without inverting a tet is taken
/// back. The halves are checked again. Deterministic.
AccuracyControlStats control_shape_accuracy(TetMesh& mesh, const BoundaryGeometry& geometry,
                                            const std::vector<double>& acceptable,
                                            const AccuracyControlOptions& options = {});

}  // namespace femorph
