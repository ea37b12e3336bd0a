// Delaunay edge flips of the surface triangles in Phased ODT smoothing
// (thesis 2.6.5.3, Fig. 2.45: each flip is an edge split and a collapse).
#pragma once

#include "common/types.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femorph {

class TetMesh;
struct BoundaryGeometry;

struct SurfaceFlipOptions {
  /// Per vertex slot: an edge flips only when its two vertices and the two
  /// opposite vertices have mask 1. Empty: all.
  std::vector<std::uint8_t> vertex_mask;
  /// Tets the flip makes must keep a minimum stretch (Eq. 1.1) of at least
  /// this (see flip_surface_edges).
  double min_stretch = 0.05;
  /// On a region without a fit (BoundaryGeometry::discrete): an edge flips
  /// only when the new pair of triangles is within this times the longer
  /// diagonal of the old pair (the distance between the two diagonals).
  /// 0.02 is below the chord error the input's own triangles have on a
  /// round (L / 8R = 0.03 for edges L a quarter of the radius R).
  double max_deviation = 0.02;
  /// Passes over the boundary faces; stops early after a pass without flips.
  int max_passes = 4;
};

struct SurfaceFlipStats {
  std::size_t flips = 0;    // edges flipped
  std::size_t refused = 0;  // edges that qualified but were refused (tet quality or TetMesh)
};

/// Flips surface edges (a, b) between two boundary triangles (a, b, c),
/// (b, a, d) of one fitted region, or of an unfitted one with kept
/// triangles when nearly flat (max_deviation), not curve edges, when the pair is not
/// Delaunay (angle at c + angle at d > pi), the quad is convex (the new
/// triangles keep the orientation of the old ones) and the flip raises the
/// smaller minimum angle of the two triangles. The tets the flip makes are
/// computed beforehand (the ring tets of (a, b) without c, with a or b
/// replaced by c): their minimum stretch must reach min(before, min_stretch)
/// on planes, and both min_stretch and the ring's minimum before on curved
/// and unfitted regions (where the flip moves the discrete surface). Then
/// TetMesh::flip_surface_edge, which checks validity exactly. Boundary faces
/// in tet id order: deterministic.
SurfaceFlipStats flip_surface_edges(TetMesh& mesh, const BoundaryGeometry& geometry,
                                    const SurfaceFlipOptions& options = {});

}  // namespace femorph
