// The quality of a vertex's ball (its incident tets) with the vertex moved:
// the quality guard every smoothing and relocation step of Improve shares.
#pragma once

#include "common/types.h"

#include <vector>

namespace femorph {

class TetMesh;

/// Minimum stretch (Eq. 1.1) over the tets of `ball` with vertex v placed at
/// p (v = kInvalidIndex: the tets as they are).
double ball_min_stretch(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p);

/// The quality guard of the smoothing steps (beyond the thesis): moving v
/// to p must not lower the ball's minimum stretch (`old_min`, from
/// ball_min_stretch at v's position), and no tet of the ball at or above
/// `floor` may fall below it. Without the second rule a ball that already
/// holds a near-flat tet lets a move spoil its good tets down to that tet's
/// level (seen on a real part, fandisk, with jittered inner vertices).
bool move_keeps_quality(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v, const Vec3& p,
                        double old_min, double floor);

}  // namespace femorph
