// ODT smoothing of the surface triangles, phase (2) of Phased ODT smoothing
// (thesis 2.6.5.3, Eq. 2.34, Fig. 2.43 and 2.44).
#pragma once

#include "common/types.h"
#include "improve/odt_smooth_volume.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace femorph {

class TetMesh;
struct BoundaryGeometry;

/// Options of the boundary phases (1) and (2) of Phased ODT smoothing.
struct BoundarySmoothOptions {
  /// Sweeps over the vertices (Gauss-Seidel; the surface smoother goes
  /// colour by colour).
  int iterations = 3;
  /// Per vertex slot: only vertices with mask 1 move. Empty: all may move.
  std::vector<std::uint8_t> vertex_mask;
  /// Stop when no vertex moved farther than tolerance times its mean edge
  /// length in a sweep.
  double tolerance = 1e-4;
  /// Step halvings of alpha_ODT (Eq. 2.34) before a vertex is left in place.
  int max_halvings = 6;
  /// Accept a step only when the minimum stretch (Eq. 1.1) over the vertex's
  /// tet ball does not decrease.
  bool quality_guard = true;
  /// With the guard, no tet of the ball at or above this stretch may fall
  /// below it (move_keeps_quality()).
  double quality_floor = 0.3;
  /// Acceptable geometric error per region (2.6.4, control_shape_accuracy.h);
  /// when given, a move may not take a boundary edge of a curved region
  /// beyond it (chords_within_error()). Null: not checked.
  const std::vector<double>* acceptable_error = nullptr;
  /// Beyond the thesis (relax_edge_lengths): when set, a vertex moves toward
  /// the rest position of springs along all its edges, each as long as
  /// 1 / edge_density at the edge's midpoint (OdtSmoothOptions::edge_density),
  /// the step taken in the parameter plane instead of Eq. 2.34's.
  std::function<double(const Vec3&)> edge_density;
  /// With the guard: a ball above guard_keep may lose this fraction of its
  /// minimum stretch, down to guard_keep (OdtSmoothOptions::guard_drop).
  double guard_drop = 0;
  double guard_keep = 0.35;
  /// For tests (odt_smooth_surface): each ball minimum the quality guard
  /// reads from the stretches kept per tet is also computed from the mesh;
  /// OdtSmoothReport counts both and the disagreements.
  bool check_stretch_cache = false;
};

/// Moves each vertex whose constraint is VertexConstraint::Surface (one
/// fitted region) by Eq. 2.34 over its 1-ring of boundary triangles, computed
/// in a 2D parameter plane of the region around the vertex (Fig. 2.43/2.44):
///   plane     the plane itself (orthonormal frame at the vertex)
///   cylinder  the development: (R * azimuth, axial), azimuth relative to v
///   cone      the development about the apex: polar coordinates
///             (distance to apex s, azimuth * sin(half angle))
///   sphere    a spherical coordinate system with v on its equator:
///             (R * azimuth, R * latitude)
///   torus     toroidal and poloidal angles relative to v, scaled to lengths
///             at v: ((R + r cos phi_v) * theta, r * phi)
/// c_tau is the triangle's circumcentre in that plane, or its barycentre when
/// the triangle has a vertex off the region's interior (class not Surface) or
/// is not Delaunay (strictly inside its circumcircle in the plane: another
/// vertex of v's 1-ring, or the vertex across its outer edge in the same
/// region; a local form of the Delaunay condition, which keeps far-off
/// circumcentres of slivers out). The new point is mapped back and projected onto the
/// fitted surface (project_to_constraint), so every accepted position is on
/// it. Step alpha = 1, halved while the move would invert a tet (exact,
/// TetMesh::move_vertex), fold a ring triangle in the parameter plane or, with
/// the quality guard, lower the ball's minimum stretch. The vertices move
/// colour by colour (Gauss-Seidel between colours), each colour in parallel:
/// no two vertices of a colour read each other's position (the vertices of
/// their balls and their opposite vertices). The colours are made greedily
/// in id order, so the result does not depend on the number of threads.
/// Corner, curve and unfitted-region vertices do not move.
OdtSmoothReport odt_smooth_surface(TetMesh& mesh, const BoundaryGeometry& geometry,
                                   const BoundarySmoothOptions& options = {});

}  // namespace femorph
