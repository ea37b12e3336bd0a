// TetMesh::sort_spatially: vertices renumbered along a Morton curve and tets
// by their lowest vertex, so that neighbours sit close in memory again after
// edits have scattered them.
#include "mesh/tet_mesh.h"
#include "common/parallel.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace femorph {

std::vector<index_t> TetMesh::sort_spatially() {
  const index_t nv = vertex_slots(), nt = tet_slots();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (index_t v = 0; v < nv; ++v)
    if (vertex_alive(v)) {
      lo = lo.cwiseMin(points_[v]);
      hi = hi.cwiseMax(points_[v]);
    }
  // Vertices by their Morton code (21 bits per axis, interleaved), then id.
  const auto spread = [](std::uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
  };
  const Vec3 scale = Vec3::Constant(2097151.0).cwiseQuotient((hi - lo).cwiseMax(Vec3::Constant(1e-300)));
  std::vector<std::pair<std::uint64_t, index_t>> vkeys(static_cast<std::size_t>(nv), {~0ULL, kInvalidIndex});
  parallel_for(nv, [&](long i) {
    const index_t v = static_cast<index_t>(i);
    if (!vertex_alive(v)) return;
    const Vec3 u = (points_[v] - lo).cwiseProduct(scale);
    vkeys[v] = {spread(static_cast<std::uint64_t>(u.x())) | spread(static_cast<std::uint64_t>(u.y())) << 1 |
                    spread(static_cast<std::uint64_t>(u.z())) << 2,
                v};
  });
  std::sort(vkeys.begin(), vkeys.end());
  while (!vkeys.empty() && vkeys.back().second == kInvalidIndex) vkeys.pop_back();
  const index_t new_nv = static_cast<index_t>(vkeys.size());
  std::vector<index_t> vmap(static_cast<std::size_t>(nv), kInvalidIndex);
  for (index_t i = 0; i < new_nv; ++i) vmap[vkeys[i].second] = i;
  // Tets by their lowest new vertex id, then old id (a counting sort).
  std::vector<index_t> first(static_cast<std::size_t>(nt), kInvalidIndex);
  std::vector<index_t> start(static_cast<std::size_t>(new_nv) + 1, 0);
  parallel_for(nt, [&](long i) {
    const index_t t = static_cast<index_t>(i);
    if (!tet_alive(t)) return;
    const Tet& T = rec_[t].v;
    first[t] = std::min({vmap[T[0]], vmap[T[1]], vmap[T[2]], vmap[T[3]]});
    fetch_add(start[first[t] + 1], index_t(1));
  });
  for (index_t i = 0; i < new_nv; ++i) start[i + 1] += start[i];
  const index_t new_nt = start[new_nv];
  std::vector<index_t> order(static_cast<std::size_t>(new_nt)), tmap(static_cast<std::size_t>(nt), kInvalidIndex);
  for (index_t t = 0; t < nt; ++t)
    if (first[t] >= 0) {
      tmap[t] = start[first[t]]++;
      order[tmap[t]] = t;
    }

  const std::size_t nnv = static_cast<std::size_t>(new_nv);
  const std::unique_ptr<Vec3[]> points(new Vec3[nnv]);
  const std::unique_ptr<VertexClass[]> vclass(new VertexClass[nnv]);
  std::vector<VertexStencil> vorigin(nnv);
  const std::unique_ptr<index_t[]> vtet(new index_t[nnv]);
  parallel_for(new_nv, [&](long i) {
    const index_t v = vkeys[static_cast<std::size_t>(i)].second;
    points[i] = points_[v];
    vclass[i] = vclass_[v];
    vorigin[static_cast<std::size_t>(i)] = vertex_origin_[v];
    vtet[i] = tmap[vertex_tet_[v]];
  });
  // Not value-initialised: no serial pass zeroes them; the parallel writes
  // below touch the pages first.
  const std::unique_ptr<TetRecord[]> rec(new TetRecord[static_cast<std::size_t>(new_nt)]);
  const std::unique_ptr<index_t[]> torigin(new index_t[static_cast<std::size_t>(new_nt)]);
  parallel_for(new_nt, [&](long i) {
    const index_t t = order[static_cast<std::size_t>(i)];
    for (int k = 0; k < 4; ++k) {
      rec[i].v[k] = vmap[rec_[t].v[k]];
      const index_t code = rec_[t].n[k];
      rec[i].n[k] = code >= 0 ? (tmap[code >> 2] << 2 | (code & 3)) : code;  // boundary codes hold the region
    }
    torigin[i] = tet_origin_[t];
  });
  // Copied back rather than swapped: the old arrays keep their capacity, so
  // the next edits grow them without reallocating. In parallel, into arrays
  // no longer than before (nothing to fill).
  points_.resize(nnv);
  vclass_.resize(nnv);
  vertex_origin_.resize(nnv);
  vertex_tet_.resize(nnv);
  parallel_for(new_nv, [&](long i) {
    points_[static_cast<std::size_t>(i)] = points[static_cast<std::size_t>(i)];
    vclass_[static_cast<std::size_t>(i)] = vclass[static_cast<std::size_t>(i)];
    vertex_origin_[static_cast<std::size_t>(i)] = vorigin[static_cast<std::size_t>(i)];
    vertex_tet_[static_cast<std::size_t>(i)] = vtet[static_cast<std::size_t>(i)];
  });
  rec_.resize(static_cast<std::size_t>(new_nt));
  tet_origin_.resize(static_cast<std::size_t>(new_nt));
  parallel_for(new_nt, [&](long i) {
    rec_[static_cast<std::size_t>(i)] = rec[static_cast<std::size_t>(i)];
    tet_origin_[static_cast<std::size_t>(i)] = torigin[static_cast<std::size_t>(i)];
  });
  free_tets_.clear();
  free_vertices_.clear();
  tet_marks_.reset(rec_.size());
  link_stamps_.reset(points_.size());
  touched_.clear();
  return vmap;
}

}  // namespace femorph
