#include "improve/coloured_balls.h"

#include "common/parallel.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <memory>

namespace femorph {

ColouredBalls coloured_balls(const TetMesh& mesh, const std::vector<std::uint8_t>& vertex_mask) {
  const index_t slots = mesh.vertex_slots();
  const bool use_mask = !vertex_mask.empty();
  std::vector<index_t> index(static_cast<std::size_t>(slots), kInvalidIndex);
  std::vector<index_t> ids;
  for (index_t v = 0; v < slots; ++v) {
    if (!mesh.vertex_alive(v) || mesh.vertex_class(v) != VertexClass::Inner) continue;
    if (use_mask && (static_cast<std::size_t>(v) >= vertex_mask.size() || !vertex_mask[v])) continue;
    index[v] = static_cast<index_t>(ids.size());
    ids.push_back(v);
  }
  // Balls in id order (CSR over the live tets), each ball's tets in slot
  // order. Counted and filled in parallel, then each ball sorted: the same
  // lists as a serial scan.
  const long slots_t = mesh.tet_slots();
  // The loops over the balls run in parallel when the tet loops do.
  const long min_items = parallel_when(slots_t >= kParallelMinItems);
  std::vector<index_t> start(ids.size() + 1, 0);
  parallel_for(slots_t, [&](long t) {
    if (mesh.tet_alive(static_cast<index_t>(t)))
      for (const index_t w : mesh.tet(static_cast<index_t>(t)))
        if (index[w] >= 0) fetch_add(start[static_cast<std::size_t>(index[w]) + 1], index_t(1));
  });
  for (std::size_t i = 0; i < ids.size(); ++i) start[i + 1] += start[i];
  std::vector<index_t> tets(static_cast<std::size_t>(start.back()));
  {
    std::vector<index_t> fill(start.begin(), start.end() - 1);
    parallel_for(slots_t, [&](long t) {
      if (mesh.tet_alive(static_cast<index_t>(t)))
        for (const index_t w : mesh.tet(static_cast<index_t>(t)))
          if (index[w] >= 0) {
            const index_t slot = fetch_add(fill[static_cast<std::size_t>(index[w])], index_t(1));
            tets[static_cast<std::size_t>(slot)] = static_cast<index_t>(t);
          }
    });
  }
  const long nids = static_cast<long>(ids.size());
  parallel_for(
      nids,
      [&](long i) {
        std::sort(tets.begin() + start[static_cast<std::size_t>(i)],
                  tets.begin() + start[static_cast<std::size_t>(i) + 1]);
      },
      min_items);

  // Greedy colouring in id order: deterministic, and the same whatever the
  // number of threads. A vertex's colour depends only on its neighbours
  // with a lower id, found first in parallel (each ball holds at most three
  // per tet); the serial loop then reads a few colours per vertex instead
  // of walking balls.
  const std::unique_ptr<index_t[]> lower(new index_t[3 * tets.size() + 1]);
  std::vector<index_t> lower_count(ids.size(), 0);
  parallel_for(
      nids,
      [&](long i) {
        index_t* out = lower.get() + 3 * static_cast<std::size_t>(start[static_cast<std::size_t>(i)]);
        index_t n = 0;
        for (index_t k = start[static_cast<std::size_t>(i)]; k < start[static_cast<std::size_t>(i) + 1]; ++k)
          for (const index_t w : mesh.tet(tets[static_cast<std::size_t>(k)])) {
            const index_t j = index[w];
            if (j >= 0 && j < i && std::find(out, out + n, j) == out + n) out[n++] = j;
          }
        lower_count[static_cast<std::size_t>(i)] = n;
      },
      min_items);
  std::vector<int> colour(ids.size(), -1);
  std::vector<char> used;
  int colours = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    used.assign(static_cast<std::size_t>(colours) + 1, 0);
    const index_t* in = lower.get() + 3 * static_cast<std::size_t>(start[i]);
    for (index_t k = 0; k < lower_count[i]; ++k) used[static_cast<std::size_t>(colour[static_cast<std::size_t>(in[k])])] = 1;
    int c = 0;
    while (used[c]) ++c;
    colour[i] = c;
    colours = std::max(colours, c + 1);
  }

  ColouredBalls out;
  out.colour_start.assign(static_cast<std::size_t>(colours) + 1, 0);
  for (const int c : colour) ++out.colour_start[c + 1];
  for (int c = 0; c < colours; ++c) out.colour_start[c + 1] += out.colour_start[c];
  std::vector<std::size_t> slot(out.colour_start.begin(), out.colour_start.end() - 1);
  std::vector<std::size_t> order(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) order[slot[colour[i]]++] = i;
  out.vertices.resize(ids.size());
  out.ball_start.assign(ids.size() + 1, 0);
  for (std::size_t j = 0; j < order.size(); ++j) {
    const std::size_t i = order[j];
    out.vertices[j] = ids[i];
    out.ball_start[j + 1] = out.ball_start[j] + static_cast<std::size_t>(start[i + 1] - start[i]);
  }
  out.ball_tets.resize(tets.size());
  const long nout = static_cast<long>(order.size());
  parallel_for(
      nout,
      [&](long j) {
        const std::size_t i = order[static_cast<std::size_t>(j)];
        std::copy(tets.begin() + start[i], tets.begin() + start[i + 1],
                  out.ball_tets.begin() + static_cast<std::ptrdiff_t>(out.ball_start[static_cast<std::size_t>(j)]));
      },
      min_items);
  return out;
}

}  // namespace femorph
