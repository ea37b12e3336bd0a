// Reader for ASCII Medit .mesh files (INRIA's format, as written by MMG,
// TetGen -g, Gmsh and many research codes). The real test parts in
// shared/realparts (fandisk, chamfer) come in this format.
#pragma once

#include "common/types.h"

#include <array>
#include <string>
#include <vector>

namespace femorph {

/// What a Medit file holds that FEMorph uses. Indices are 0-based; the
/// `*_refs` vectors run parallel to the entities (Medit's per-entity
/// reference number, e.g. a region or surface id).
struct MeditMesh {
  std::vector<Vec3> points;
  std::vector<index_t> point_refs;
  std::vector<Tet> tets;  // as in the file: not reoriented
  std::vector<index_t> tet_refs;
  std::vector<std::array<index_t, 3>> triangles;
  std::vector<index_t> triangle_refs;
};

/// Reads an ASCII Medit .mesh file: MeshVersionFormatted 1 to 4 (the text is
/// the same; 1 and 2 are the common ones), Dimension 3, sections Vertices,
/// Tetrahedra and Triangles. Every other section (Edges, Corners, Ridges,
/// RequiredVertices, Normals, Quadrilaterals, ...) is skipped, as are
/// `#` comments. Keywords are matched case-insensitively. Sections may come
/// in any order; the file ends at `End` or at its end.
///
/// On failure `mesh` is left empty and the Status message names the file,
/// the line and section where reading stopped and the problem: missing or
/// unreadable file, not a Medit file, Dimension other than 3, negative or
/// absurd counts, a section cut short (end of file or the next keyword where
/// a number was due), a non-numeric or non-integer token, a vertex index out
/// of range, or a section given twice.
Status read_medit_mesh(const std::string& path, MeditMesh& mesh);

}  // namespace femorph
