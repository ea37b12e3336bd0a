#include "quality/check_validity.h"
#include "common/parallel.h"

#include "geometry/predicates.h"

#include <utility>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace femorph {
namespace {

// Local vertices of the face opposite local vertex f, ordered so that the
// right-hand normal points out of a positive tet. Written here on purpose
// rather than taken from mesh/, which this checker checks.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
constexpr std::size_t kMaxListed = 10;

// Union-find over dense ids 0..n-1, path halving; the smaller id becomes the
// root. reset() reuses the storage.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n = 0) { reset(n); }
  void reset(std::size_t n) {
    parent_.resize(n);
    for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::int64_t>(i);
  }
  std::int64_t find(std::int64_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::int64_t a, std::int64_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }
  std::size_t roots() {
    std::size_t count = 0;
    for (std::size_t i = 0; i < parent_.size(); ++i)
      count += find(static_cast<std::int64_t>(i)) == static_cast<std::int64_t>(i);
    return count;
  }

 private:
  std::vector<std::int64_t> parent_;
};

// A tet face in a bucket of faces sharing their smallest id: the other two
// ids (mid << 32 | max), the face code 4t + f with the parity of its outward
// order appended ((4t + f) << 1 | parity), and the tet's opposite vertex.
// Everything the matching needs, so it never goes back to the tets.
struct FaceRecord {
  std::uint64_t key;
  std::uint32_t code_parity;
  index_t opposite;
  index_t code() const { return static_cast<index_t>(code_parity >> 1); }
  index_t tet() const { return static_cast<index_t>(code_parity >> 3); }
  int parity() const { return code_parity & 1; }
  bool operator<(const FaceRecord& o) const {
    return key < o.key || (key == o.key && code_parity < o.code_parity);
  }
};

// A usable tet's ids and, per face f, the code 4t' + f' of the face across it
// when exactly two tets share it (else -1): one cache line for two tets.
struct TetLinks {
  Tet ids;
  std::array<index_t, 4> across;
};

// An edge of a boundary face: (min << 32 | max) and the boundary face index.
struct EdgeRecord {
  std::uint64_t key;
  std::int64_t face;
  bool operator<(const EdgeRecord& o) const {
    return key < o.key || (key == o.key && face < o.face);
  }
};

std::uint64_t pair_key(index_t lo, index_t hi) {
  return (static_cast<std::uint64_t>(lo) << 32) | static_cast<std::uint32_t>(hi);
}

// The face of tet t opposite local vertex f, as ids in outward order.
std::array<index_t, 3> face_ids(const Tet& t, int f) {
  return {t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]]};
}

// Parity of the permutation that sorts three distinct ids: equal parities
// mean the same cyclic order.
int parity(const std::array<index_t, 3>& v) {
  return ((v[0] > v[1]) + (v[0] > v[2]) + (v[1] > v[2])) & 1;
}

int local_index(const std::array<index_t, 3>& f, index_t v) {
  for (int k = 0; k < 3; ++k)
    if (f[k] == v) return k;
  return -1;
}

void list_first(const std::vector<std::uint8_t>& bad, std::vector<index_t>& out) {
  out.clear();
  for (std::size_t i = 0; i < bad.size() && out.size() < kMaxListed; ++i)
    if (bad[i]) out.push_back(static_cast<index_t>(i));
}

// Per-tet and per-point flags shared by the steps of check_validity.
struct Flags {
  std::vector<std::uint8_t> usable;     // ids in range and distinct
  std::vector<std::uint8_t> used;       // point used by some tet
  std::vector<std::uint8_t> bad_tet;    // listed in first_bad_tets
  std::vector<std::uint8_t> bad_point;  // listed in first_bad_vertices
  std::vector<std::uint8_t> skip_link;  // a face or edge at the point is already flagged
};

// 1-2. Ids in range and distinct; coordinates finite.
void check_input(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                 ValidityReport& report, Flags& flags) {
  const std::size_t num_points = points.size();
  std::vector<std::uint8_t> finite(num_points);
  for (std::size_t v = 0; v < num_points; ++v) {
    finite[v] = points[v].allFinite();
    if (!finite[v]) {
      ++report.nonfinite_points;
      flags.bad_point[v] = 1;
    }
  }
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& tet = tets[t];
    bool in_range = true;
    for (index_t v : tet) {
      if (v < 0 || static_cast<std::size_t>(v) >= num_points)
        in_range = false;
      else
        flags.used[v] = 1;
    }
    if (!in_range) {
      ++report.index_out_of_range;
      flags.bad_tet[t] = 1;
    } else if (tet[0] == tet[1] || tet[0] == tet[2] || tet[0] == tet[3] || tet[1] == tet[2] ||
               tet[1] == tet[3] || tet[2] == tet[3]) {
      ++report.repeated_vertex;
      flags.bad_tet[t] = 1;
    } else {
      flags.usable[t] = 1;
      if (!(finite[tet[0]] && finite[tet[1]] && finite[tet[2]] && finite[tet[3]]))
        flags.bad_tet[t] = 1;
    }
  }
}

// 3. Exact sign of every usable tet with finite points.
void check_orientation(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                       ValidityReport& report, Flags& flags) {
  const std::int64_t num_tets = static_cast<std::int64_t>(tets.size());
  using Counts = std::pair<std::size_t, std::size_t>;  // (inverted, degenerate)
  const Counts counts = parallel_reduce(
      static_cast<long>(num_tets), Counts(0, 0),
      [&](long begin, long end, int) {
        Counts k(0, 0);
        for (long t = begin; t < end; ++t) {
          if (!flags.usable[t] || flags.bad_tet[t]) continue;  // bad ids or a non-finite point
          const Tet& tet = tets[static_cast<std::size_t>(t)];
          const int sign = orient3d_sign(points[tet[0]], points[tet[1]], points[tet[2]], points[tet[3]]);
          k.first += sign < 0;
          k.second += sign == 0;
          if (sign <= 0) flags.bad_tet[t] = 1;
        }
        return k;
      },
      [](Counts a, Counts b) { return Counts(a.first + b.first, a.second + b.second); });
  report.inverted = counts.first;
  report.degenerate = counts.second;
}

// 4. Matches the faces of usable tets: buckets them by their smallest id
// (counting sort) and sorts each bucket by the other two. Fills links (if
// not null), boundary (ids in outward order) and boundary_tet.
void match_faces(std::size_t num_points, const std::vector<Tet>& tets, ValidityReport& report,
                 Flags& flags, std::vector<TetLinks>* links,
                 std::vector<std::array<index_t, 3>>& boundary,
                 std::vector<index_t>& boundary_tet) {
  std::vector<std::int64_t> bucket_start(num_points + 1, 0);
  for (std::size_t t = 0; t < tets.size(); ++t) {
    if (!flags.usable[t]) continue;
    const Tet& tet = tets[t];
    for (int f = 0; f < 4; ++f) {
      index_t lo = tet[(f + 1) % 4];
      for (int k = 2; k < 4; ++k) lo = std::min(lo, tet[(f + k) % 4]);
      ++bucket_start[lo + 1];
    }
  }
  for (std::size_t v = 0; v < num_points; ++v) bucket_start[v + 1] += bucket_start[v];
  std::vector<FaceRecord> faces(bucket_start[num_points]);
  {
    std::vector<std::int64_t> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (std::size_t t = 0; t < tets.size(); ++t) {
      if (!flags.usable[t]) continue;
      for (int f = 0; f < 4; ++f) {
        const std::array<index_t, 3> outward = face_ids(tets[t], f);
        std::array<index_t, 3> v = outward;
        std::sort(v.begin(), v.end());
        const std::uint32_t code = static_cast<std::uint32_t>(4 * t + f);
        faces[fill[v[0]]++] = {pair_key(v[1], v[2]),
                               (code << 1) | static_cast<std::uint32_t>(parity(outward)),
                               tets[t][f]};
      }
    }
  }
  parallel_for(
      static_cast<long>(num_points),
      [&](long v) { std::sort(faces.begin() + bucket_start[v], faces.begin() + bucket_start[v + 1]); },
      kParallelMinItems, 4096);

  for (std::size_t lo = 0; lo < num_points; ++lo) {
    const std::int64_t end = bucket_start[lo + 1];
    for (std::int64_t first = bucket_start[lo]; first < end;) {
      std::int64_t last = first + 1;
      while (last < end && faces[last].key == faces[first].key) ++last;
      const FaceRecord& r0 = faces[first];
      const index_t mid = static_cast<index_t>(r0.key >> 32);
      const index_t max = static_cast<index_t>(r0.key & 0xffffffffu);

      // Duplicates: equal opposite vertices, counted once per extra copy, at
      // the face made of the tet's three smallest ids.
      for (std::int64_t j = first + 1; j < last; ++j) {
        if (faces[j].opposite < max) continue;
        for (std::int64_t i = first; i < j; ++i)
          if (faces[i].opposite == faces[j].opposite) {
            ++report.duplicate_tets;
            flags.bad_tet[faces[i].tet()] = flags.bad_tet[faces[j].tet()] = 1;
            break;
          }
      }

      if (last - first == 1) {
        const index_t v0 = static_cast<index_t>(lo);
        boundary.push_back(r0.parity() == 0 ? std::array<index_t, 3>{v0, mid, max}
                                            : std::array<index_t, 3>{v0, max, mid});
        boundary_tet.push_back(r0.tet());
      } else if (last - first == 2) {
        const FaceRecord& r1 = faces[first + 1];
        if (r0.parity() == r1.parity()) {
          ++report.orientation_mismatches;
          flags.bad_tet[r0.tet()] = flags.bad_tet[r1.tet()] = 1;
        }
        if (links) {
          (*links)[r0.tet()].across[r0.code() % 4] = r1.code();
          (*links)[r1.tet()].across[r1.code() % 4] = r0.code();
        }
      } else {
        ++report.overshared_faces;
        for (std::int64_t i = first; i < last; ++i) flags.bad_tet[faces[i].tet()] = 1;
        flags.skip_link[lo] = flags.skip_link[mid] = flags.skip_link[max] = 1;
      }
      first = last;
    }
  }
  report.boundary_faces = boundary.size();
}

// 5 and 6(b). Sorts the edges of the boundary faces; flags edges without
// exactly two faces and returns, per point, the number of fans its boundary
// faces form (boundary-face corners joined across manifold edges).
std::vector<std::int32_t> boundary_fans(std::size_t num_points,
                                        const std::vector<std::array<index_t, 3>>& boundary,
                                        const std::vector<index_t>& boundary_tet,
                                        ValidityReport& report, Flags& flags) {
  std::vector<EdgeRecord> edges;
  edges.reserve(3 * boundary.size());
  for (std::size_t b = 0; b < boundary.size(); ++b)
    for (int k = 0; k < 3; ++k) {
      const index_t u = boundary[b][k], w = boundary[b][(k + 1) % 3];
      edges.push_back({pair_key(std::min(u, w), std::max(u, w)), static_cast<std::int64_t>(b)});
    }
  std::sort(edges.begin(), edges.end());
  DisjointSets corners(3 * boundary.size());
  for (std::size_t first = 0; first < edges.size();) {
    std::size_t last = first + 1;
    while (last < edges.size() && edges[last].key == edges[first].key) ++last;
    const index_t u = static_cast<index_t>(edges[first].key >> 32);
    const index_t w = static_cast<index_t>(edges[first].key & 0xffffffffu);
    if (last - first == 2) {
      // The two faces continue each other's fan around u and around w.
      const std::int64_t b0 = edges[first].face, b1 = edges[first + 1].face;
      for (index_t v : {u, w})
        corners.unite(3 * b0 + local_index(boundary[b0], v), 3 * b1 + local_index(boundary[b1], v));
    } else {
      ++report.nonmanifold_boundary_edges;
      flags.skip_link[u] = flags.skip_link[w] = 1;
      flags.bad_point[u] = flags.bad_point[w] = 1;
      for (std::size_t i = first; i < last; ++i) flags.bad_tet[boundary_tet[edges[i].face]] = 1;
    }
    first = last;
  }
  std::vector<std::int32_t> fans(num_points, 0);
  for (std::size_t b = 0; b < boundary.size(); ++b)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t corner = 3 * static_cast<std::int64_t>(b) + k;
      if (corners.find(corner) == corner) ++fans[boundary[b][k]];
    }
  return fans;
}

// 6. Per point, over its ball (the usable tets containing it): (a) the tets
// joined across manifold faces containing the point form one component;
// (b) at most one boundary fan; (c) the link's Euler characteristic
// V - E + F (V the point's edges, E its faces, F its tets) is 2 without
// boundary fan (sphere) and 1 with one (disk).
void check_vertices(const std::vector<TetLinks>& links, const std::vector<std::int32_t>& fans,
                    ValidityReport& report, Flags& flags) {
  const std::size_t num_points = fans.size();
  // Point -> usable tets, in increasing tet order (CSR).
  std::vector<std::int64_t> ball_start(num_points + 1, 0);
  for (std::size_t t = 0; t < links.size(); ++t)
    if (flags.usable[t])
      for (index_t v : links[t].ids) ++ball_start[v + 1];
  for (std::size_t v = 0; v < num_points; ++v) ball_start[v + 1] += ball_start[v];
  std::vector<index_t> ball(ball_start[num_points]);
  {
    std::vector<std::int64_t> fill(ball_start.begin(), ball_start.end() - 1);
    for (std::size_t t = 0; t < links.size(); ++t)
      if (flags.usable[t])
        for (index_t v : links[t].ids) ball[fill[v]++] = static_cast<index_t>(t);
  }

  std::vector<std::uint8_t> nonmanifold(num_points, 0);
  // Per thread: sets over positions in one ball; per point, the last point
  // whose link saw it.
  std::vector<DisjointSets> components_by(static_cast<std::size_t>(parallel_threads()));
  std::vector<std::vector<index_t>> seen_by(components_by.size());
  parallel_for_worker(
      static_cast<long>(num_points),
      [&](long v, int worker) {
        DisjointSets& components = components_by[static_cast<std::size_t>(worker)];
        std::vector<index_t>& seen = seen_by[static_cast<std::size_t>(worker)];
        if (seen.empty()) seen.assign(num_points, kInvalidIndex);
        const index_t* begin = ball.data() + ball_start[v];
        const index_t* end = ball.data() + ball_start[v + 1];
        const std::int64_t degree = end - begin;
        if (degree == 0) return;
        components.reset(degree);
        std::int64_t link_vertices = 0, link_edges = 0;
        for (std::int64_t i = 0; i < degree; ++i) {
          const index_t t = begin[i];
          const TetLinks& tet = links[t];
          for (int f = 0; f < 4; ++f) {
            const index_t w = tet.ids[f];
            if (w == v) continue;
            if (seen[w] != v) {
              seen[w] = static_cast<index_t>(v);
              ++link_vertices;
            }
            // Face f contains v; across it (if manifold) lies tet t2.
            const index_t across = tet.across[f];
            const index_t t2 = across < 0 ? kInvalidIndex : across / 4;
            if (t2 < t) ++link_edges;  // each face once
            if (t2 > t) components.unite(i, std::lower_bound(begin, end, t2) - begin);
          }
        }
        bool bad = components.roots() > 1 || fans[v] > 1;
        if (!bad && !flags.skip_link[v]) bad = link_vertices - link_edges + degree != (fans[v] == 0 ? 2 : 1);
        if (bad) nonmanifold[v] = 1;
      },
      kParallelMinItems, 1024);
  report.nonmanifold_vertices = static_cast<std::size_t>(std::count(nonmanifold.begin(), nonmanifold.end(), 1));
  for (std::size_t v = 0; v < num_points; ++v)
    if (nonmanifold[v]) {
      flags.bad_point[v] = 1;
      for (std::int64_t k = ball_start[v]; k < ball_start[v + 1]; ++k) flags.bad_tet[ball[k]] = 1;
    }
}

}  // namespace

bool ValidityReport::ok() const {
  return index_out_of_range == 0 && repeated_vertex == 0 && nonfinite_points == 0 &&
         inverted == 0 && degenerate == 0 && overshared_faces == 0 &&
         orientation_mismatches == 0 && duplicate_tets == 0 &&
         nonmanifold_boundary_edges == 0 && nonmanifold_vertices == 0 &&
         dangling_vertices == 0;
}

std::string ValidityReport::summary() const {
  std::ostringstream out;
  if (ok()) {
    out << "valid: " << tets << " tets, " << points << " points, " << boundary_faces
        << " boundary faces";
    return out.str();
  }
  auto line = [&](std::size_t count, const char* one, const char* many, const char* detail) {
    if (count) out << count << ' ' << (count == 1 ? one : many) << detail << '\n';
  };
  line(index_out_of_range, "tet", "tets", " with a point id out of range");
  line(repeated_vertex, "tet", "tets", " using a point twice");
  line(nonfinite_points, "point", "points", " with a non-finite coordinate");
  line(inverted, "inverted tet", "inverted tets", " (negative volume)");
  line(degenerate, "degenerate tet", "degenerate tets", " (zero volume)");
  line(overshared_faces, "face", "faces", " shared by more than two tets");
  line(orientation_mismatches, "interior face", "interior faces",
       " with the same orientation in both its tets");
  line(duplicate_tets, "duplicate tet", "duplicate tets", " (same four points as another)");
  line(nonmanifold_boundary_edges, "boundary edge", "boundary edges",
       " without exactly two boundary faces");
  line(nonmanifold_vertices, "non-manifold vertex", "non-manifold vertices",
       " (tets not face-connected, several boundary fans, or a link that is not a disk or sphere)");
  line(dangling_vertices, "dangling point", "dangling points", " (used by no tet)");
  auto ids = [&](const char* what, const std::vector<index_t>& list) {
    if (list.empty()) return;
    out << "first bad " << what << ':';
    for (index_t i : list) out << ' ' << i;
    out << '\n';
  };
  ids("tets", first_bad_tets);
  ids("points", first_bad_vertices);
  std::string text = out.str();
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

ValidityReport check_validity(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                              const ValidityOptions& options) {
  ValidityReport report;
  report.points = points.size();
  report.tets = tets.size();
  Flags flags;
  flags.usable.assign(tets.size(), 0);
  flags.bad_tet.assign(tets.size(), 0);
  flags.used.assign(points.size(), 0);
  flags.bad_point.assign(points.size(), 0);
  flags.skip_link.assign(points.size(), 0);

  check_input(points, tets, report, flags);
  if (options.require_positive) check_orientation(points, tets, report, flags);

  std::vector<TetLinks> links;
  if (options.check_manifold) {
    links.resize(tets.size());
    for (std::size_t t = 0; t < tets.size(); ++t)
      links[t] = {tets[t], {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex}};
  }
  std::vector<std::array<index_t, 3>> boundary;
  std::vector<index_t> boundary_tet;
  match_faces(points.size(), tets, report, flags, options.check_manifold ? &links : nullptr,
              boundary, boundary_tet);

  if (options.check_manifold) {
    const std::vector<std::int32_t> fans =
        boundary_fans(points.size(), boundary, boundary_tet, report, flags);
    check_vertices(links, fans, report, flags);
  }

  // 7. Dangling points.
  if (options.check_dangling)
    for (std::size_t v = 0; v < points.size(); ++v)
      if (!flags.used[v]) {
        ++report.dangling_vertices;
        flags.bad_point[v] = 1;
      }

  list_first(flags.bad_tet, report.first_bad_tets);
  list_first(flags.bad_point, report.first_bad_vertices);
  return report;
}

}  // namespace femorph
