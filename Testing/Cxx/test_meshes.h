// Meshes built at run time for tests and benchmarks.
#pragma once

#include "common/types.h"

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace femorph {
namespace testing {

struct TestMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  std::vector<Tet> face_regions;  // per tet face: region id on the boundary, -1 inside
};

/// The unit cube [0, 1]^3 cut into n^3 cells of 6 tets each (Kuhn's
/// subdivision: every cell split along its main diagonal, so neighbouring
/// cells match). Vertices are jittered by up to `jitter` times the cell size,
/// interior ones in 3D, boundary ones within their face or edge only, corners
/// not at all, so the cube's shape and volume stay exact. Boundary faces get
/// regions 0..5 for the planes x=0, x=1, y=0, y=1, z=0, z=1. All tets are
/// positively oriented when jitter < 0.15 or so.
inline TestMesh make_cube_mesh(int n, double jitter, std::uint64_t seed) {
  TestMesh m;
  const int n1 = n + 1;
  const double h = 1.0 / n;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto id = [n1](int i, int j, int k) { return static_cast<index_t>((k * n1 + j) * n1 + i); };
  m.points.resize(static_cast<std::size_t>(n1) * n1 * n1);
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Vec3 p(i * h, j * h, k * h);
        const int idx[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          const double d = u(rng) * jitter * h;  // drawn always: same stream for any n
          if (idx[a] != 0 && idx[a] != n) p[a] += d;
        }
        m.points[id(i, j, k)] = p;
      }
  // Kuhn subdivision: one tet per permutation of the axes, walking from the
  // cell's (0,0,0) corner to its (1,1,1) corner.
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& perm : perms) {
          int c[3] = {i, j, k};
          Tet t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[perm[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          // Odd permutations give negative tets: swap two vertices.
          const Vec3& p0 = m.points[t[0]];
          if ((m.points[t[1]] - p0).dot((m.points[t[2]] - p0).cross(m.points[t[3]] - p0)) < 0) std::swap(t[1], t[2]);
          m.tets.push_back(t);
        }
  // Regions: a face is on plane x=0 when its three vertices have i == 0, etc.
  static const int face_local[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  m.face_regions.assign(m.tets.size(), Tet{{-1, -1, -1, -1}});
  auto grid = [n1](index_t v, int axis) {
    const int i = v % n1, j = (v / n1) % n1, k = v / (n1 * n1);
    return axis == 0 ? i : (axis == 1 ? j : k);
  };
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f)
      for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
          const int target = side ? n : 0;
          bool all = true;
          for (int q = 0; q < 3; ++q) all = all && grid(m.tets[t][face_local[f][q]], axis) == target;
          if (all) m.face_regions[t][f] = 2 * axis + side;
        }
  return m;
}

/// Sum of signed tet volumes.
inline double total_volume(const std::vector<Vec3>& p, const std::vector<Tet>& tets) {
  double v = 0;
  for (const Tet& t : tets) v += (p[t[1]] - p[t[0]]).dot((p[t[2]] - p[t[0]]).cross(p[t[3]] - p[t[0]])) / 6.0;
  return v;
}

}  // namespace testing
}  // namespace femorph
