// Inverted element removal, thesis 2.6.2 (Fig. 2.39): half-edge collapses
// chosen to maximise the minimum stretch (Eq. 1.1) around the kept vertex.
#pragma once

#include "common/types.h"
#include "improve/remove_degenerate_elements.h"  // ProjectVertexFn

#include <cstddef>
#include <vector>

namespace femorph {

class TetMesh;

struct InvertedRemovalOptions {
  /// Safety bound on passes over the inverted tets. Every pass but the last
  /// removes at least one inverted tet, so at most 2 #inverted + 1 are made.
  int max_passes = 100000;
  /// When no half-edge collapse of an inverted tet succeeds, try moving its
  /// vertices (untangle_vertex; not in the thesis).
  bool relocate_vertices = true;
  /// Projection for moved surface vertices on curved regions (see
  /// untangle_vertex); empty: only vertices on planar regions move.
  ProjectVertexFn project;
};

struct InvertedRemovalStats {
  std::size_t initial_inverted = 0;
  std::size_t collapses = 0;           ///< accepted half-edge collapses
  std::size_t relocations = 0;         ///< vertices moved by untangle_vertex
  std::size_t remaining_inverted = 0;  ///< tets still with negative volume
  /// Ids of the inverted tets no half-edge collapse of theirs could repair.
  std::vector<index_t> remaining_tets;
  double min_stretch_before = 0;  ///< over all live tets
  double min_stretch_after = 0;
};

/// Thesis 2.6.2: for each inverted tet (negative volume; build the mesh with
/// BuildOptions::allow_inverted), lowest stretch first, tries the half-edge
/// collapses of its six edges in both directions and keeps the accepted one
/// that maximises the minimum stretch around the kept vertex (Fig. 2.39;
/// collapse_min_stretch()).
/// Only directions that thesis Fig. 2.37 allows are tried: the edge is not
/// forbidden (A)-(C) and the removed vertex is not more constrained than the
/// kept one, so boundary vertices only slide along their own face or curve
/// (the boundary keeps its shape where it is planar). TetMesh::collapse_edge
/// validates that every remaining tet of the removed vertex's ball is
/// positive; inverted tets elsewhere in the kept vertex's ball do not block
/// it (they are not changed), so each accepted collapse lowers the number of
/// inverted tets. When inverted tets block each other (each in the ball of
/// the vertex another's collapse would remove), one collapse by
/// TetMesh::half_edge_collapse_keeping_inverted() breaks the cycle. Repeats
/// in passes until none is left or neither kind of collapse succeeds; then,
/// if options.relocate_vertices, the vertices of the remaining inverted tets
/// are moved by untangle_vertex() and the passes resume.
/// Limits: tangles of several folded boundary triangles (surface vertices
/// slid past each other within a face) can stay, because a surface vertex may
/// only be collapsed onto another vertex of its own face and a move must make
/// its whole ball positive at once; they are listed in remaining_tets.
/// They are rare: surface vertices slid by up to 0.99 cell per axis leave a
/// few in a few meshes (test DegenerateRemoval.CaseCSweep bounds them).
/// Deterministic.
InvertedRemovalStats remove_inverted_elements(TetMesh& mesh, const InvertedRemovalOptions& options = {});

}  // namespace femorph
