// Recombination of a tet mesh into a hex-dominant mesh (thesis 4.5, after
// Meshkat & Talmor 2000 and Botella 2016): local search of hex, prism and
// pyramid candidates on the extended RF-graph (A1), then greedy adoption by
// the priority of Eq. 4.1 (A2). No vertex is added or moved.
#pragma once

#include "common/types.h"
#include "hex/mixed_cells.h"

#include <functional>
#include <vector>

namespace femorph {

struct TetToHexParams {
  /// delta_angle of 4.5.3 as an angle: QUAD(t1, t2) succeeds when the two
  /// triangles' normals differ by at most this, i.e. the cosine of the
  /// dihedral angle of the quad reaches cos(quad_angle_deg) (less 1e-12, so
  /// that exactly coplanar triangles pass at 0). Degrees, in [0, 180].
  double quad_angle_deg = 20.0;
  /// Beyond the thesis: a candidate is adopted only when its minimum scaled
  /// Jacobian (Eq. 4.2) reaches this (pyramids: over their base corners).
  double min_scaled_jacobian = 0.2;
  bool hexahedra = true;
  bool prisms = true;
  bool pyramids = true;
  /// Leave no quad face meeting two triangles of other cells: after the
  /// greedy pass, cap such quads with a pyramid (or any candidate whose quads
  /// all match) where one fits, dissolve the cells still offending back into
  /// tets until none is left, then adopt the candidates on the tets left
  /// whose quads all match (see dissolve_nonconformal_cells.cpp).
  bool refuse_nonconformal = false;
  /// Progress, called from the calling thread now and then with the fraction
  /// done in [0, 1] and the step's name; returning false stops the run,
  /// which then fails with the message "aborted". Empty: no reports.
  std::function<bool(double fraction, const char* step)> progress;
};

/// Per-kind figures, indexed by CellKind (Tetra, Pyramid, Wedge, Hexahedron).
struct TetToHexStats {
  std::array<std::size_t, 4> candidates{};  // cells found by the local search (QUAD passed)
  std::array<std::size_t, 4> admissible{};  // of those, reaching min_scaled_jacobian (one per tet set)
  std::array<std::size_t, 4> cells{};       // in the output
  std::array<double, 4> volume{};           // per kind: the sum of its source tets' volumes
  double total_volume = 0;
  std::size_t nonconformal_interfaces = 0;  // quad faces meeting two triangles
  std::size_t dissolved_nonconformal = 0;   // adopted, then dissolved (refuse_nonconformal)
  double seconds_adjacency = 0;  // face adjacency (LINK edges) and input checks
  double seconds_search = 0, seconds_adopt = 0, seconds_total = 0;
};

struct TetToHexResult {
  /// Hexes, wedges, pyramids (each kind by smallest source tet), then the
  /// tets left in input order; VTK node orders, positive volume.
  MixedCells cells;
  std::vector<index_t> source_offsets{ 0 };  // input tets of output cell c:
  std::vector<index_t> source_tets;          //   source_tets[source_offsets[c] .. [c + 1]), sorted
  std::vector<double> min_scaled_jacobian;   // per output cell (Eq. 4.2)
  TetToHexStats stats;
};

/// A1 + A2. points and positively oriented, conforming tets; fails with a
/// message (and an empty result) on NaN coordinates, a tet referring to a
/// missing point or repeating one, an inverted or flat tet (exact test), a
/// face shared by more than two tets or two tets on the same side of a
/// face, or parameters out of range. An empty mesh gives an empty result.
Status recombine_tetrahedra(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                            const TetToHexParams& params, TetToHexResult& result);

}  // namespace femorph
