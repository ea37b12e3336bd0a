// The vertices a parallel pass moves and their balls, grouped by colour: no
// two vertices of one colour share a tet, so the moves of one colour are
// independent and may run concurrently (ODT smoothing, the worst-vertex
// search of the finishing step).
#pragma once

#include "common/types.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femorph {

class TetMesh;

/// The topology does not change during such a pass, so the balls are
/// gathered once.
struct ColouredBalls {
  std::vector<index_t> vertices;          ///< candidate vertices, by colour then id
  std::vector<std::size_t> colour_start;  ///< vertices[colour_start[c] .. colour_start[c + 1])
  std::vector<std::size_t> ball_start;    ///< per entry of `vertices`
  std::vector<index_t> ball_tets;         ///< each ball's tets in slot order
};

/// The inner vertices with vertex_mask set (empty: all inner vertices),
/// greedily coloured in id order: deterministic and the same for any number
/// of threads.
ColouredBalls coloured_balls(const TetMesh& mesh, const std::vector<std::uint8_t>& vertex_mask);

}  // namespace femorph
