// Independent validity checker for tetrahedral meshes given as plain arrays.
//
// Deliberately shares no code with TetMesh (mesh/tet_mesh.h): it matches faces
// by its own sort of sorted vertex triples and decides orientation with the
// exact predicate femorph::orient3d_sign, so tests can use it to check the
// mesh class and its local operations.
#pragma once

#include "common/types.h"

#include <cstddef>
#include <string>
#include <vector>

namespace femorph {

/// Which families of checks check_validity runs. A disabled family leaves its
/// counts at 0, so ValidityReport::ok() ignores it.
struct ValidityOptions {
  /// Flag tets with zero or negative volume (exact sign): `inverted`,
  /// `degenerate`. Off for meshes whose orientation is not FEMorph's yet.
  bool require_positive = true;
  /// Check the neighbourhood of every edge and vertex:
  /// `nonmanifold_boundary_edges`, `nonmanifold_vertices`.
  bool check_manifold = true;
  /// Flag points no tet uses: `dangling_vertices`.
  bool check_dangling = true;
};

/// What check_validity found. Tets and points are counted as given; each
/// problem count is the number of distinct offending tets, faces, edges or
/// points (a tet with two bad ids counts once).
struct ValidityReport {
  std::size_t tets = 0, points = 0;
  /// Faces of exactly one tet (among tets with valid, distinct ids).
  std::size_t boundary_faces = 0;

  // Input sanity (always checked).
  std::size_t index_out_of_range = 0;  ///< tets with an id < 0 or >= #points
  std::size_t repeated_vertex = 0;     ///< tets using one point twice
  std::size_t nonfinite_points = 0;    ///< points with a NaN or infinite coordinate

  // Geometry (require_positive), exact sign of (p1-p0).((p2-p0)x(p3-p0)).
  std::size_t inverted = 0;    ///< sign < 0
  std::size_t degenerate = 0;  ///< sign == 0 (four coplanar points)

  // Conformity (always checked).
  std::size_t overshared_faces = 0;        ///< faces of more than two tets
  std::size_t orientation_mismatches = 0;  ///< interior faces both tets traverse in the same cyclic order
  std::size_t duplicate_tets = 0;          ///< tets whose vertex set an earlier tet already has

  // Manifoldness (check_manifold).
  std::size_t nonmanifold_boundary_edges = 0;  ///< boundary edges with != 2 boundary faces
  std::size_t nonmanifold_vertices = 0;        ///< see check_validity

  // Unused points (check_dangling).
  std::size_t dangling_vertices = 0;  ///< points used by no tet

  /// Up to 10 offending tet ids and point ids, ascending, for messages.
  std::vector<index_t> first_bad_tets;
  std::vector<index_t> first_bad_vertices;

  /// True when every problem count is zero.
  bool ok() const;
  /// One line per nonzero problem count, e.g. "3 inverted tets (negative
  /// volume)", then the first offending ids. For a valid mesh a single line
  /// "valid: T tets, P points, B boundary faces".
  std::string summary() const;
};

/// Checks that a tet mesh is a valid finite-element mesh: conforming,
/// consistently and positively oriented, manifold, without duplicates or
/// unused points.
///
/// Inputs:
///   points   #P positions
///   tets     #T tets, 0-based ids into points, VTK_TETRA order; positive
///            when (p1 - p0) . ((p2 - p0) x (p3 - p0)) > 0
///   options  which families of checks to run (ValidityOptions)
/// Returns a ValidityReport.
///
/// Cost: O(T log T) time and about 100 bytes per tet; partly parallel (common/parallel.h).
/// Faster with ids in spatial order than randomly shuffled (cache misses).
///
/// Checks, in order:
///  1. Ids: every id in [0, #P) and the four ids distinct. Tets failing this
///     take no further part (their in-range ids still count as used).
///  2. Points: every coordinate finite (all points, used or not). Tets on a
///     non-finite point are listed as bad and skip the orientation check.
///  3. Orientation (require_positive): exact sign of each tet's volume.
///  4. Conformity: faces are matched by their sorted vertex triples (bucketed
///     by smallest id, then sorted). A face of one tet is a boundary face; of
///     two tets an interior face, which the two must traverse in opposite
///     cyclic orders (face opposite local vertex f ordered so that a positive
///     tet's normal points out); a face of three or more tets is overshared.
///     Two tets on a face with the same opposite vertex are duplicates (a
///     duplicate pair also shows as 4 mismatched faces, or, mirrored, as an
///     inverted tet).
///  5. Manifold boundary (check_manifold): every edge of a boundary face lies
///     on exactly two boundary faces (with 4, the boundary is then a closed,
///     consistently oriented 2-manifold away from its vertices).
///  6. Manifold vertices (check_manifold): a vertex is non-manifold when
///     (a) its tets are not connected through faces that contain it and
///     are shared by exactly two tets (so the vertices of an overshared face
///     usually count here too), or
///     (b) its boundary faces form more than one fan (edge-connected cycle),
///     or, when (a) and (b) pass and none of its faces or edges is already
///     flagged by 4 or 5,
///     (c) its link (tets as triangles, faces as edges, edges as vertices) is
///     not a sphere (interior vertex: Euler characteristic 2) or a disk
///     (boundary vertex: 1), e.g. a cone over a torus.
///  7. Dangling points (check_dangling): points no tet uses.
/// Not checked: geometric self-intersection of the boundary or of tets that
/// share no face (a folded mesh with consistent orientation shows up as
/// inverted tets in 3, but two separate pieces overlapping in space do not).
ValidityReport check_validity(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                              const ValidityOptions& options = {});

}  // namespace femorph
