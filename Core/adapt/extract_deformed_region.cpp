// The deformed region K_Df of thesis 3.4.3 (Fig. 3.5): the G_v cells whose
// centres lie in G_d's box (C_v1), of which those nearer than the threshold
// to the moving object (C_v2); the space tets holding their vertices.
// Beyond the thesis: the region is closed into a manifold submesh, so that it
// can be adapted as a mesh of its own and spliced back.
#include "adapt/adapt.h"

#include <algorithm>
#include <cmath>

namespace femorph {

namespace {

/// Whether the part of v's ball inside the region, and the part outside it
/// (other tets and the domain's outside together), are each face-connected
/// around v. A vertex where either is split pinches the region's boundary.
bool ball_is_manifold(const TetMesh& mesh, index_t v, const std::vector<index_t>& ball,
                      const std::vector<std::uint8_t>& in_region) {
  const std::size_t n = ball.size();
  // Union-find over the ball's tets plus one node for the outside.
  std::vector<std::size_t> parent(n + 1);
  for (std::size_t i = 0; i <= n; ++i) parent[i] = i;
  const auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  const auto unite = [&](std::size_t a, std::size_t b) { parent[find(a)] = find(b); };
  const auto local = [&](index_t t) {
    return static_cast<std::size_t>(std::find(ball.begin(), ball.end(), t) - ball.begin());
  };
  bool outside_used = false;
  for (std::size_t i = 0; i < n; ++i) {
    const index_t t = ball[i];
    const int lv = mesh.local_index(t, v);
    for (int f = 0; f < 4; ++f) {
      if (f == lv) continue;  // the link face: not around v
      const index_t code = mesh.adjacency(t, f);
      if (code < 0) {
        if (!in_region[t]) {
          unite(i, n);
          outside_used = true;
        }
        continue;
      }
      const std::size_t j = local(code >> 2);
      if (j < n && in_region[t] == in_region[ball[j]]) unite(i, j);
    }
  }
  std::size_t region_roots = 0, other_roots = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (find(i) != i) continue;
    (in_region[ball[i]] ? region_roots : other_roots) += 1;
  }
  if (outside_used && find(n) == n) ++other_roots;
  else if (!outside_used) {
    // A boundary face of a region tet at v: the outside touches the region.
    for (std::size_t i = 0; i < n && !outside_used; ++i) {
      const int lv = mesh.local_index(ball[i], v);
      for (int f = 0; f < 4; ++f)
        if (f != lv && mesh.is_boundary_face(ball[i], f)) outside_used = true;
    }
    if (outside_used) ++other_roots;
  }
  return region_roots <= 1 && other_roots <= 1;
}

/// The vertices of the region's tets, each once, into `candidates`.
void queue_vertices(const TetMesh& mesh, const std::vector<index_t>& region, std::vector<std::uint8_t>& queued,
                    std::vector<index_t>& candidates) {
  for (const index_t t : region)
    for (const index_t v : mesh.tet(t))
      if (!queued[v]) {
        queued[v] = 1;
        candidates.push_back(v);
      }
}

}  // namespace

void close_region(const TetMesh& mesh, std::vector<index_t>& region, const std::function<bool(index_t)>& may_take) {
  std::vector<std::uint8_t> in_region(static_cast<std::size_t>(mesh.tet_slots()), 0);
  for (const index_t t : region) in_region[t] = 1;
  std::vector<index_t> ball, candidates;
  const auto take_ball = [&](index_t v) {
    mesh.vertex_ball(v, ball);
    for (const index_t t : ball) {
      if (in_region[t] || !may_take(t)) continue;
      in_region[t] = 1;
      region.push_back(t);
    }
  };
  // Closing: a vertex of the region whose ball is pinched takes its whole
  // space ball in; the tets added bring new vertices to check.
  std::vector<std::uint8_t> queued(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  queue_vertices(mesh, region, queued, candidates);
  for (std::size_t q = 0; q < candidates.size(); ++q) {
    const index_t v = candidates[q];
    mesh.vertex_ball(v, ball);
    // A ball all in the region, off the domain's boundary, is not pinched.
    if (!mesh.on_boundary(v) && std::all_of(ball.begin(), ball.end(), [&](index_t t) { return in_region[t] != 0; }))
      continue;
    if (ball_is_manifold(mesh, v, ball, in_region)) continue;
    const std::size_t before = region.size();
    take_ball(v);
    for (std::size_t r = before; r < region.size(); ++r)
      for (const index_t w : mesh.tet(region[r])) {
        if (!queued[w]) {
          queued[w] = 1;
          candidates.push_back(w);
        } else if (w != v) {
          candidates.push_back(w);  // its ball changed: check it again
        }
      }
  }
}

void open_region(const TetMesh& mesh, std::vector<index_t>& region) {
  std::vector<std::uint8_t> in_region(static_cast<std::size_t>(mesh.tet_slots()), 0);
  for (const index_t t : region) in_region[t] = 1;
  std::vector<index_t> ball, candidates;
  std::vector<std::uint8_t> queued(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  queue_vertices(mesh, region, queued, candidates);
  for (std::size_t q = 0; q < candidates.size(); ++q) {
    const index_t v = candidates[q];
    mesh.vertex_ball(v, ball);
    if (std::none_of(ball.begin(), ball.end(), [&](index_t t) { return in_region[t] != 0; })) continue;
    if (!mesh.on_boundary(v) && std::all_of(ball.begin(), ball.end(), [&](index_t t) { return in_region[t] != 0; }))
      continue;
    if (ball_is_manifold(mesh, v, ball, in_region)) continue;
    for (const index_t t : ball) {
      if (!in_region[t]) continue;
      in_region[t] = 0;
      for (const index_t w : mesh.tet(t))
        if (w != v) candidates.push_back(w);
    }
  }
  region.erase(std::remove_if(region.begin(), region.end(), [&](index_t t) { return !in_region[t]; }), region.end());
}

std::vector<index_t> extract_deformed_region(const TetMesh& mesh, const std::vector<int>& material_by_origin,
                                             const VertexGrid& vg, const DistanceGrid& dg,
                                             const RigidPose& to_object, double threshold) {
  const auto is_space = [&](index_t t) {
    const index_t o = mesh.tet_origin(t);
    return o >= 0 && static_cast<std::size_t>(o) < material_by_origin.size() && material_by_origin[o] == 0;
  };
  // G_d's box in space (its corners moved with the object).
  const RigidPose to_space = to_object.inverse();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int c = 0; c < 8; ++c) {
    Vec3 corner = dg.origin;
    for (int a = 0; a < 3; ++a)
      if (c & (1 << a)) corner[a] += dg.n[a] * dg.h;
    const Vec3 p = to_space.apply(corner);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  int c0[3], c1[3];
  for (int a = 0; a < 3; ++a) {
    c0[a] = std::max(0, static_cast<int>(std::floor((lo[a] - vg.origin[a]) / vg.h - 0.5)));
    c1[a] = std::min(vg.n[a] - 1, static_cast<int>(std::ceil((hi[a] - vg.origin[a]) / vg.h - 0.5)));
  }
  std::vector<std::uint8_t> in_region(static_cast<std::size_t>(mesh.tet_slots()), 0);
  std::vector<index_t> region, ball;
  const auto take_ball = [&](index_t v) {
    mesh.vertex_ball(v, ball);
    for (const index_t t : ball) {
      if (in_region[t] || !is_space(t)) continue;
      in_region[t] = 1;
      region.push_back(t);
    }
  };
  // C_v1 -> C_v2 -> their vertices' space tets.
  for (int k = c0[2]; k <= c1[2]; ++k)
    for (int j = c0[1]; j <= c1[1]; ++j)
      for (int i = c0[0]; i <= c1[0]; ++i) {
        const std::size_t cell = vg.cell_id(i, j, k);
        if (vg.start[cell] == vg.start[cell + 1]) continue;
        const Vec3 centre = vg.origin + vg.h * Vec3(i + 0.5, j + 0.5, k + 0.5);
        if (!(dg.at(to_object.apply(centre)) < threshold)) continue;
        for (index_t s = vg.start[cell]; s < vg.start[cell + 1]; ++s) take_ball(vg.vertices[s]);
      }
  close_region(mesh, region, is_space);
  return region;
}

}  // namespace femorph
