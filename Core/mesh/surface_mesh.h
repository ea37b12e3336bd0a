// SurfaceMesh: a closed triangulated surface with adjacency, normals and
// areas; the boundary of a tet mesh, on which the segmentation (thesis 2.4)
// works.
#pragma once

#include "common/types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace femorph {

class TetMesh;

using Tri = std::array<index_t, 3>;

struct SurfaceMesh {
  std::vector<Vec3> points;             // #P surface vertices
  std::vector<Tri> triangles;           // #F, counter-clockwise seen from outside
  /// neighbors[f][k]: triangle across edge (triangles[f][k], triangles[f][(k+1)%3]),
  /// -1 on an open edge.
  std::vector<Tri> neighbors;
  std::vector<Vec3> normals;            // unit outward normal per triangle (0 if degenerate)
  std::vector<double> areas;            // per triangle
  /// Triangles around each vertex (CSR): vertex_triangles[vertex_offsets[v] ..
  /// vertex_offsets[v + 1]).
  std::vector<index_t> vertex_offsets, vertex_triangles;
  double mean_edge_length = 0;
  /// Where the surface came from, when built from a tet mesh: the tet mesh
  /// vertex of each surface vertex, and 4 * tet + local face of each triangle.
  std::vector<index_t> source_vertex;
  std::vector<index_t> source_face;

  index_t num_points() const { return static_cast<index_t>(points.size()); }
  index_t num_triangles() const { return static_cast<index_t>(triangles.size()); }
};

/// What build_surface_mesh found.
struct SurfaceReport {
  std::size_t open_edges = 0;           // edges with one triangle
  std::size_t nonmanifold_edges = 0;    // edges with more than two
  std::size_t misoriented_edges = 0;    // two triangles running the same way along it
  std::size_t degenerate_triangles = 0; // zero area
};

/// Builds adjacency, normals, areas and vertex-triangle incidence. Fails (with
/// the counts in the message) on non-manifold edges, on edges whose two
/// triangles disagree in orientation, and on open edges unless `allow_open`;
/// also on an index out of range, a triangle repeating a vertex or a
/// non-finite point. On failure `out` is left empty (the report is filled). Degenerate triangles are counted, not refused (their normal
/// is zero; the segmentation treats them as unknown).
Status build_surface_mesh(std::vector<Vec3> points, std::vector<Tri> triangles, SurfaceMesh& out,
                          bool allow_open = false, SurfaceReport* report = nullptr);

/// The boundary of a tet mesh as a SurfaceMesh (outward triangles), with
/// source_vertex and source_face filled.
Status extract_boundary_surface(const TetMesh& mesh, SurfaceMesh& out, SurfaceReport* report = nullptr);

/// The boundary triangles with a vertex flagged in `vertices` (per vertex
/// slot), so every flagged boundary vertex has its whole fan: an open
/// surface around a region, without a pass over the whole boundary's
/// adjacency.
Status extract_boundary_surface_near(const TetMesh& mesh, const std::vector<std::uint8_t>& vertices, SurfaceMesh& out);

}  // namespace femorph
