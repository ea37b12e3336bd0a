// The Delaunay condition of thesis 2.6.5.4, tested locally, and the
// circumcentre c_tau of Eq. 2.28.
#pragma once

#include "common/types.h"

namespace femorph {

class TetMesh;

/// True when no face neighbour's opposite vertex lies strictly inside the
/// circumsphere of live tet t (exact insphere). The local form of "no vertex
/// outside the tet lies in its circumsphere".
bool locally_delaunay(const TetMesh& mesh, index_t t);

/// Circumcentre of tet (a, b, c, d); false (and *centre untouched) when the
/// tet is too flat for it to be meaningful.
bool tet_circumcentre(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Vec3* centre);

}  // namespace femorph
