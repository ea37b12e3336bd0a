// TetMesh::build: the input checks, the orientation, face matching into the
// adjacency codes, the manifold checks and the vertex classes (thesis
// Fig. 2.37) of a mesh given as points and tets.
#include "mesh/tet_mesh.h"
#include "common/huge_pages.h"
#include "common/parallel.h"

#include "geometry/predicates.h"
#include "mesh/tet_mesh_internal.h"

#include <utility>
#include <functional>
#include <array>
#include <cstdint>
#include <algorithm>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <string>

namespace femorph {

namespace {

/// A face within its bucket (the bucket is its smallest vertex): the other
/// two vertices, ascending, as one key, and where it came from.
struct FaceRecord {
  std::uint64_t key;  // second << 32 | third vertex id
  index_t code;       // 4 * t + f
  bool odd;           // the tet's face order is an odd permutation of the sorted ids
  bool same_face(const FaceRecord& o) const { return key == o.key; }
};

std::string plural(std::size_t n, const char* one, const char* many) {
  std::ostringstream s;
  s << n << ' ' << (n == 1 ? one : many);
  return s.str();
}

}  // namespace

Status TetMesh::build(std::vector<Vec3> points, std::vector<Tet> tets, const BuildOptions& options,
                      BuildReport* report_out) {
  *this = TetMesh();
  BuildReport report;
  const index_t nv = static_cast<index_t>(points.size());
  const std::size_t nt = tets.size();
  auto fail = [this](std::string msg) {
    *this = TetMesh();
    return Status::failure(std::move(msg));
  };
  if (nt == 0) return fail("the mesh has no tetrahedra");
  if (nt > static_cast<std::size_t>(std::numeric_limits<index_t>::max() / 4))
    return fail("the mesh has too many tetrahedra for 32-bit ids");
  if (!options.face_regions.empty() && options.face_regions.size() != nt)
    return fail("face_regions has " + std::to_string(options.face_regions.size()) + " rows for " +
                std::to_string(nt) + " tets");
  // Region ids are labels (a sub-mesh keeps its part's ids); the bound keeps
  // the boundary code -2 - region far from overflowing.
  constexpr index_t max_region = std::numeric_limits<index_t>::max() / 2;
  for (std::size_t t = 0; t < options.face_regions.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const index_t r = options.face_regions[t][f];
      if (r < -1 || r > max_region)
        return fail("face_regions names region " + std::to_string(r) + " at tet " + std::to_string(t) + ", face " +
                    std::to_string(f) + " (ids are -1 or in [0, " + std::to_string(max_region) + "])");
    }

  // The passes over every point, tet or face run in parallel where they
  // are independent (the result does not depend on the number of threads).
  const long npoints = static_cast<long>(points.size()), ntets = static_cast<long>(nt);
  const std::size_t nonfinite = parallel_reduce(
      npoints, std::size_t(0),
      [&](long begin, long end, int) {
        std::size_t k = 0;
        for (long i = begin; i < end; ++i) k += !points[static_cast<std::size_t>(i)].allFinite();
        return k;
      },
      std::plus<std::size_t>());
  if (nonfinite) return fail(plural(nonfinite, "point has", "points have") + " NaN or infinite coordinates");

  for (std::size_t t = 0; t < nt; ++t) {
    const Tet& T = tets[t];
    for (int i = 0; i < 4; ++i) {
      if (T[i] < 0 || T[i] >= nv)
        return fail("tet " + std::to_string(t) + " refers to point " + std::to_string(T[i]) +
                    ", out of range [0, " + std::to_string(nv) + ")");
      for (int j = 0; j < i; ++j)
        if (T[i] == T[j])
          return fail("tet " + std::to_string(t) + " uses point " + std::to_string(T[i]) + " twice");
    }
  }

  // Orientation: count signs exactly; an all-negative input is flipped.
  std::vector<signed char> sign(nt);
  using Signs = std::array<std::size_t, 3>;  // positive, negative, zero
  const Signs signs = parallel_reduce(
      ntets, Signs{},
      [&](long begin, long end, int) {
        Signs k{};
        for (long i = begin; i < end; ++i) {
          const std::size_t t = static_cast<std::size_t>(i);
          const Tet& T = tets[t];
          sign[t] = static_cast<signed char>(orient3d_sign(points[T[0]], points[T[1]], points[T[2]], points[T[3]]));
          k[0] += sign[t] > 0;
          k[1] += sign[t] < 0;
          k[2] += sign[t] == 0;
        }
        return k;
      },
      [](Signs a, const Signs& b) {
        return Signs{a[0] + b[0], a[1] + b[1], a[2] + b[2]};
      });
  std::size_t npos = signs[0], nneg = signs[1];
  const std::size_t nzero = signs[2];
  std::vector<Tet> regions = options.face_regions;
  if (nneg > npos) {
    // The other convention: swapping local vertices 1 and 2 flips every tet;
    // faces 1 and 2 swap with them.
    for (std::size_t t = 0; t < nt; ++t) {
      std::swap(tets[t][1], tets[t][2]);
      sign[t] = static_cast<signed char>(-sign[t]);
      if (!regions.empty()) std::swap(regions[t][1], regions[t][2]);
    }
    std::swap(npos, nneg);
    report.flipped_tets = nt;
  }

  // Face matching: the faces, keyed by their sorted vertex triple, go into
  // buckets by their smallest vertex (a counting sort), then a small sort
  // inside each bucket: linear in practice, where one global sort of the
  // 4 #T faces is not. A face's two copies share a bucket, so the buckets
  // are matched independently. The records are written straight into their
  // buckets from several threads (no array of records is zeroed first); the
  // sort by key and then code makes the order unique.
  const auto face_record = [&tets](std::size_t t, int f, index_t* bucket) {
    index_t v[3];
    for (int k = 0; k < 3; ++k) v[k] = tets[t][kTetFace[f][k]];
    FaceRecord r;
    r.odd = internal::sort3_parity(v);
    *bucket = v[0];
    r.key = static_cast<std::uint64_t>(static_cast<std::uint32_t>(v[1])) << 32 | static_cast<std::uint32_t>(v[2]);
    r.code = static_cast<index_t>(4 * t + f);
    return r;
  };
  // The tets are cut into a few parts; each part's faces are counted per
  // bucket and written into the part's own share of each bucket (the same
  // parts in both loops), so no counter is shared between threads: no
  // atomics. A few more parts than threads, so that a thread on a busy core
  // takes fewer of them (each part holds a count per vertex).
  std::vector<index_t> start(static_cast<std::size_t>(nv) + 1, 0);
  const auto faces = huge_page_array<FaceRecord>(4 * nt);
  {
    const int threads = ntets >= kParallelMinItems ? parallel_threads() : 1;
    const long parts = threads > 1 ? threads + 2L : 1;
    const long part = std::max(1L, (ntets + parts - 1) / parts);
    std::vector<std::vector<index_t>> fill(static_cast<std::size_t>(parts));
    parallel_for_chunks(
        ntets,
        [&](long begin, long end, int) {
          std::vector<index_t>& mine = fill[static_cast<std::size_t>(begin / part)];
          mine.assign(static_cast<std::size_t>(nv), 0);
          for (long i = begin; i < end; ++i) {
            const Tet& T = tets[static_cast<std::size_t>(i)];
            for (int f = 0; f < 4; ++f)
              ++mine[static_cast<std::size_t>(std::min({T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]}))];
          }
        },
        kParallelMinItems, part);
    // Bucket starts, then each part's offset inside each bucket (parts left
    // empty by a short range have no counts).
    index_t next = 0;
    for (index_t v = 0; v < nv; ++v) {
      start[static_cast<std::size_t>(v)] = next;
      for (std::vector<index_t>& counts : fill) {
        if (counts.empty()) continue;
        index_t& count = counts[static_cast<std::size_t>(v)];
        const index_t n = count;
        count = next;
        next += n;
      }
    }
    start[static_cast<std::size_t>(nv)] = next;
    parallel_for_chunks(
        ntets,
        [&](long begin, long end, int) {
          std::vector<index_t>& mine = fill[static_cast<std::size_t>(begin / part)];
          for (long i = begin; i < end; ++i)
            for (int f = 0; f < 4; ++f) {
              index_t bucket;
              const FaceRecord r = face_record(static_cast<std::size_t>(i), f, &bucket);
              faces[static_cast<std::size_t>(mine[static_cast<std::size_t>(bucket)]++)] = r;
            }
        },
        kParallelMinItems, part);
  }
  const auto by_key_then_code = [](const FaceRecord& x, const FaceRecord& y) {
    return x.key < y.key || (x.key == y.key && x.code < y.code);
  };
  parallel_for(
      nv, [&](long v) { std::sort(&faces[start[v]], &faces[start[v + 1]], by_key_then_code); }, kParallelMinItems,
      4096);

  rec_.reserve(nt);
  advise_huge_pages(rec_.data(), nt * sizeof(TetRecord));
  rec_.resize(nt);
  parallel_for(ntets, [&](long t) {
    rec_[static_cast<std::size_t>(t)] = TetRecord{tets[static_cast<std::size_t>(t)], Tet{{-1, -1, -1, -1}}};
  });
  std::vector<Tet>().swap(tets);
  std::vector<char> offending(nt, 0);
  using Matches = std::array<std::size_t, 3>;  // overshared, mismatched, boundary
  const Matches matches = parallel_reduce(
      nv, Matches{},
      [&](long vbegin, long vend, int) {
        std::size_t overshared = 0, mismatched = 0, boundary = 0;
        for (index_t v = static_cast<index_t>(vbegin); v < static_cast<index_t>(vend); ++v)
          for (std::size_t i = static_cast<std::size_t>(start[v]), last = static_cast<std::size_t>(start[v + 1]);
               i < last;) {
            std::size_t j = i + 1;
            while (j < last && faces[j].same_face(faces[i])) ++j;
            if (j - i == 1) {
              ++boundary;
              const index_t t = faces[i].code >> 2, f = faces[i].code & 3;
              const index_t region = regions.empty() ? kInvalidIndex : std::max<index_t>(regions[t][f], -1);
              rec_[t].n[f] = internal::boundary_code(region);
            } else if (j - i == 2) {
              const index_t a = faces[i].code, b = faces[i + 1].code;
              rec_[a >> 2].n[a & 3] = b;
              rec_[b >> 2].n[b & 3] = a;
              // Two tets agree on orientation when they traverse the shared face in
              // opposite cyclic orders.
              if (faces[i].odd == faces[i + 1].odd) {
                ++mismatched;
                const index_t ta = a >> 2, tb = b >> 2;
                // Blame the tet whose volume sign is the minority one.
                __atomic_store_n(&offending[sign[ta] < 0 ? ta : (sign[tb] < 0 ? tb : ta)], char(1), __ATOMIC_RELAXED);
              }
            } else {
              overshared += j - i;
            }
            i = j;
          }
        return Matches{overshared, mismatched, boundary};
      },
      [](Matches a, const Matches& b) {
        return Matches{a[0] + b[0], a[1] + b[1], a[2] + b[2]};
      },
      kParallelMinItems, 4096);
  const std::size_t overshared = matches[0], mismatched = matches[1], boundary = matches[2];
  if (overshared)
    return fail("the mesh is not conformal: " + plural(overshared, "tet face is", "tet faces are") +
                " shared by more than two tets");
  if (mismatched) {
    const std::size_t n = static_cast<std::size_t>(std::count(offending.begin(), offending.end(), 1));
    return fail("mixed orientation: " + plural(n, "tet is", "tets are") +
                " oriented opposite to their neighbours (" + plural(mismatched, "face", "faces") +
                " seen with the same orientation from both sides); fix the input's connectivity order");
  }
  report.boundary_faces = boundary;
  report.inverted_tets = nneg;
  report.degenerate_tets = nzero;
  if (nneg && !options.allow_inverted)
    return fail(plural(nneg, "tet is", "tets are") + " inverted (negative volume)");
  if (nzero && !options.allow_degenerate)
    return fail(plural(nzero, "tet has", "tets have") + " zero volume (degenerate)");

  points_ = std::move(points);
  allow_inverted_ = options.allow_inverted || options.allow_degenerate;
  tet_origin_.resize(nt);
  std::iota(tet_origin_.begin(), tet_origin_.end(), 0);
  vertex_origin_.resize(nv);
  for (index_t v = 0; v < nv; ++v) {
    vertex_origin_[v].ids[0] = v;
    vertex_origin_[v].weights[0] = 1.0;
  }
  std::vector<index_t>().swap(start);
  vertex_tet_.assign(nv, kInvalidIndex);
  std::vector<index_t> incidence(nv, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (index_t v : rec_[t].v) {
      vertex_tet_[v] = static_cast<index_t>(t);
      ++incidence[v];
    }
  for (index_t v = nv - 1; v >= 0; --v)
    if (vertex_tet_[v] < 0) {
      free_vertices_.push_back(v);
      ++report.unused_points;
    }
  vclass_.assign(nv, VertexClass::Inner);

  // Manifold vertex neighbourhoods: the ball walk must reach every incident
  // tet (otherwise local operations would see only part of the vertex).
  // The same ball classifies the vertex (used only when the build succeeds).
  // The vertices are walked in the order of their start tets, so that
  // consecutive balls share tets still in cache (the result is per vertex,
  // whatever the order).
  std::vector<index_t> walk_order;
  walk_order.reserve(static_cast<std::size_t>(nv));
  for (std::size_t t = 0; t < nt; ++t)
    for (index_t v : rec_[t].v)
      if (vertex_tet_[v] == static_cast<index_t>(t)) walk_order.push_back(v);
  using Bad = std::pair<std::size_t, index_t>;  // count, first
  std::vector<WalkMarks> marks(static_cast<std::size_t>(parallel_threads()));
  std::vector<std::vector<index_t>> balls(marks.size());
  const Bad bad = parallel_reduce(
      static_cast<long>(walk_order.size()), Bad(0, std::numeric_limits<index_t>::max()),
      [&](long begin, long end, int worker) {
        Bad k(0, std::numeric_limits<index_t>::max());
        std::vector<index_t>& ball = balls[static_cast<std::size_t>(worker)];
        for (long i = begin; i < end; ++i) {
          const index_t v = walk_order[static_cast<std::size_t>(i)];
          vertex_ball(v, ball, marks[static_cast<std::size_t>(worker)]);
          if (static_cast<index_t>(ball.size()) != incidence[v]) {
            ++k.first;
            k.second = std::min(k.second, v);
          } else {
            vclass_[v] = classify_ball(v, ball);
          }
        }
        return k;
      },
      [](Bad a, Bad b) { return Bad(a.first + b.first, std::min(a.second, b.second)); }, kParallelMinItems, 4096);
  const std::size_t nonmanifold_vertices = bad.first;
  const index_t first_bad = bad.second;
  if (nonmanifold_vertices)
    return fail("the mesh is not manifold: the tets around " +
                plural(nonmanifold_vertices, "vertex are", "vertices are") +
                " not connected through faces (e.g. point " + std::to_string(first_bad) +
                "); parts touching at a vertex or an edge are not supported");

  std::size_t bad_edges = 0, bad_fans = 0;
  internal::boundary_manifold_counts(*this, &bad_edges, &bad_fans);
  if (bad_edges)
    return fail("the boundary is not manifold: " + plural(bad_edges, "boundary edge has", "boundary edges have") +
                " other than two boundary faces");
  if (bad_fans)
    return fail("the boundary is not manifold: at " + plural(bad_fans, "vertex", "vertices") +
                " the boundary faces form more than one fan");

  if (report_out) *report_out = report;
  return Status::success();
}

}  // namespace femorph
