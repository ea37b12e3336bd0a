// Sharp edge extraction, thesis 2.4.2 (A11).
#pragma once

#include "mesh/surface_mesh.h"

#include <vector>

namespace femorph {

struct SharpEdges {
  /// Per half-edge f * 3 + k (edge k of triangle f): 1 when sharp. Both halves
  /// of an edge agree. Open edges count as sharp.
  std::vector<char> edge;
  /// Per vertex: number of sharp edges at it (a "feature vertex" has >= 3 or 1).
  std::vector<int> vertex_degree;
};

/// An edge is sharp when the angle between the normals of its two triangles
/// exceeds `angle` (radians), i.e. the dihedral angle differs from pi by more.
SharpEdges detect_sharp_edges(const SurfaceMesh& surface, double angle);

}  // namespace femorph
