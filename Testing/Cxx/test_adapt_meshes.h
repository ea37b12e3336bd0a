// The space-and-object meshes of thesis 3.7.2, built at run time for the
// Adapt tests and benchmark: a grid of cubes, a vertex at each cube's
// centre, each cube cut into 12 tets (two triangles per square face, joined
// to the centre), inner vertices jittered; material 1 on a block of cubes.
#pragma once

#include "common/types.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace femorph {
namespace testing {

struct MaterialMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  std::vector<int> material;
  Vec3 object_lo = Vec3::Zero(), object_hi = Vec3::Zero();  ///< the block at step 0
};

/// `cells` cubes of edge `edge` from the origin; the object is the `object`
/// cubes from cube `offset`, per axis (< 0: centred in the grid, rounded
/// down). Square faces are split along
/// the diagonal through their lowest-id corner, so neighbouring cubes match.
/// Vertices off the outer boundary move by up to `jitter` x edge (a move that
/// would flatten a tet is skipped), then `smooth_sweeps` half-Laplacian sweeps.
inline MaterialMesh make_block_in_box(std::array<int, 3> cells, std::array<int, 3> object, double edge,
                                      double jitter, std::uint64_t seed, std::array<int, 3> offset = {{-1, -1, -1}},
                                      int smooth_sweeps = 0) {
  MaterialMesh m;
  const int nx = cells[0], ny = cells[1], nz = cells[2];
  const auto corner = [&](int i, int j, int k) { return static_cast<index_t>((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.points.emplace_back(i * edge, j * edge, k * edge);
  std::array<int, 3> o0;
  for (int a = 0; a < 3; ++a) o0[a] = offset[a] >= 0 ? offset[a] : (cells[a] - object[a]) / 2;
  m.object_lo = Vec3(o0[0], o0[1], o0[2]) * edge;
  m.object_hi = Vec3(o0[0] + object[0], o0[1] + object[1], o0[2] + object[2]) * edge;
  const auto volume = [&](const Tet& t) {
    const Vec3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
    return (b - a).dot((c - a).cross(d - a));
  };
  // The 6 faces of a cube as corner offsets in cyclic order.
  static const int kFace[6][4][3] = {
      {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}},
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const index_t c = static_cast<index_t>(m.points.size());
        m.points.emplace_back((i + 0.5) * edge, (j + 0.5) * edge, (k + 0.5) * edge);
        const bool in_object = i >= o0[0] && i < o0[0] + object[0] && j >= o0[1] && j < o0[1] + object[1] &&
                               k >= o0[2] && k < o0[2] + object[2];
        for (const auto& face : kFace) {
          index_t q[4];
          for (int r = 0; r < 4; ++r) q[r] = corner(i + face[r][0], j + face[r][1], k + face[r][2]);
          const int low = static_cast<int>(std::min_element(q, q + 4) - q);
          const index_t a = q[low], b = q[(low + 1) % 4], cc = q[(low + 2) % 4], d = q[(low + 3) % 4];
          for (const Tet& t0 : {Tet{{a, b, cc, c}}, Tet{{a, cc, d, c}}}) {
            Tet t = t0;
            if (volume(t) < 0) std::swap(t[0], t[1]);
            m.tets.push_back(t);
            m.material.push_back(in_object ? 1 : 0);
          }
        }
      }
  // Jitter: vertices strictly inside the box, one at a time, kept when no
  // tet around falls below a fifth of its volume.
  std::vector<std::vector<index_t>> ball(m.points.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const index_t v : m.tets[t]) ball[v].push_back(static_cast<index_t>(t));
  const Vec3 hi(nx * edge, ny * edge, nz * edge);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const double tol = 1e-9 * edge;
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    const Vec3 p = m.points[v];
    const Vec3 move(u(rng), u(rng), u(rng));
    if ((p.array() < tol).any() || (p.array() > hi.array() - tol).any()) continue;
    std::vector<double> before;
    for (const index_t t : ball[v]) before.push_back(volume(m.tets[t]));
    m.points[v] = p + jitter * edge * move;
    for (std::size_t r = 0; r < ball[v].size(); ++r)
      if (volume(m.tets[ball[v][r]]) < 0.2 * before[r]) {
        m.points[v] = p;
        break;
      }
  }
  // Smoothing (the thesis smooths its jittered input): each sweep moves
  // every inner vertex halfway to the mean of its neighbours, when no tet
  // around falls below a fifth of its volume.
  std::vector<std::vector<index_t>> neighbours(m.points.size());
  for (const Tet& t : m.tets)
    for (const index_t a : t)
      for (const index_t b : t)
        if (a != b) neighbours[a].push_back(b);
  for (auto& n : neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  for (int sweep = 0; sweep < smooth_sweeps; ++sweep)
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      const Vec3 p = m.points[v];
      if ((p.array() < tol).any() || (p.array() > hi.array() - tol).any()) continue;
      Vec3 mean = Vec3::Zero();
      for (const index_t w : neighbours[v]) mean += m.points[w];
      mean /= static_cast<double>(neighbours[v].size());
      std::vector<double> before;
      for (const index_t t : ball[v]) before.push_back(volume(m.tets[t]));
      m.points[v] = 0.5 * (p + mean);
      for (std::size_t r = 0; r < ball[v].size(); ++r)
        if (volume(m.tets[ball[v][r]]) < 0.2 * before[r]) {
          m.points[v] = p;
          break;
        }
    }
  return m;
}

}  // namespace testing
}  // namespace femorph
