// TetMesh: construction, queries, classification, compaction and the
// internal-consistency check. Local operations are in their own files.
#include "mesh/tet_mesh.h"

#include "geometry/predicates.h"
#include "mesh/tet_mesh_internal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>

#include <omp.h>

namespace femorph {

const char* to_string(OpStatus status) {
  switch (status) {
    case OpStatus::Ok: return "ok";
    case OpStatus::InvalidArgument: return "invalid argument (dead element or no such edge/face)";
    case OpStatus::BoundaryEntity: return "the edge or face lies on the boundary";
    case OpStatus::WrongValence: return "wrong number of tets around the edge";
    case OpStatus::Inverted: return "a resulting tet would be inverted or flat";
    case OpStatus::DuplicateEntity: return "the new edge or face already exists";
    case OpStatus::LinkCondition: return "the link condition fails (topology would change)";
    case OpStatus::ForbiddenByRule: return "forbidden by the collapse rules of thesis Fig. 2.37";
  }
  return "unknown";
}

namespace {

/// Sorted face key and where it came from, for matching faces by sorting.
struct FaceRecord {
  index_t v[3];   // sorted vertex ids
  index_t code;   // 4 * t + f
  bool odd;       // the tet's face order is an odd permutation of v
  bool operator<(const FaceRecord& o) const {
    if (v[0] != o.v[0]) return v[0] < o.v[0];
    if (v[1] != o.v[1]) return v[1] < o.v[1];
    return v[2] < o.v[2];
  }
  bool same_face(const FaceRecord& o) const { return v[0] == o.v[0] && v[1] == o.v[1] && v[2] == o.v[2]; }
};

std::string plural(std::size_t n, const char* one, const char* many) {
  std::ostringstream s;
  s << n << ' ' << (n == 1 ? one : many);
  return s.str();
}

}  // namespace

// ---------------------------------------------------------------------------
// Construction
// ---------------------------------------------------------------------------

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

  // The passes over every point, tet or face run in parallel where they
  // are independent (the result does not depend on the number of threads).
  const long npoints = static_cast<long>(points.size()), ntets = static_cast<long>(nt);
  std::size_t nonfinite = 0;
#pragma omp parallel for schedule(static) reduction(+ : nonfinite) if (npoints >= kParallelMinItems)
  for (long i = 0; i < npoints; ++i) nonfinite += !points[static_cast<std::size_t>(i)].allFinite();
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
  std::size_t npos = 0, nneg = 0, nzero = 0;
#pragma omp parallel for schedule(static) reduction(+ : npos, nneg, nzero) if (ntets >= kParallelMinItems)
  for (long i = 0; i < ntets; ++i) {
    const std::size_t t = static_cast<std::size_t>(i);
    const Tet& T = tets[t];
    sign[t] = static_cast<signed char>(orient3d_sign(points[T[0]], points[T[1]], points[T[2]], points[T[3]]));
    npos += sign[t] > 0;
    nneg += sign[t] < 0;
    nzero += sign[t] == 0;
  }
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
  // inside each bucket: linear in practice, faster than one global sort. A
  // face's two copies share a bucket, so the buckets are matched
  // independently. The records are written straight into their buckets
  // from several threads (an array zeroed first took longer than the sort
  // at 1M tets); the sort by key and then code makes the order unique.
  const auto face_record = [&tets](std::size_t t, int f) {
    FaceRecord r;
    for (int k = 0; k < 3; ++k) r.v[k] = tets[t][kTetFace[f][k]];
    r.odd = internal::sort3_parity(r.v);
    r.code = static_cast<index_t>(4 * t + f);
    return r;
  };
  // Each thread counts its own tets' faces per bucket and writes them into
  // its own part of each bucket (the same static split of the tets in both
  // loops): no atomic counters (bench_tet_mesh, 1M tets: 407 -> 365 ms).
  std::vector<index_t> start(static_cast<std::size_t>(nv) + 1, 0);
  const std::unique_ptr<FaceRecord[]> faces(new FaceRecord[4 * nt]);
  {
    const int threads = ntets >= kParallelMinItems ? std::max(1, omp_get_max_threads()) : 1;
    std::vector<std::vector<index_t>> fill(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
    {
      const int id = omp_get_thread_num();
      std::vector<index_t>& mine = fill[static_cast<std::size_t>(id)];
      mine.assign(static_cast<std::size_t>(nv), 0);
#pragma omp for schedule(static)
      for (long i = 0; i < ntets; ++i) {
        const Tet& T = tets[static_cast<std::size_t>(i)];
        for (int f = 0; f < 4; ++f)
          ++mine[static_cast<std::size_t>(std::min({T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]}))];
      }
      // Bucket starts, then each thread's offset inside each bucket.
#pragma omp single
      {
        const std::size_t team = static_cast<std::size_t>(omp_get_num_threads());  // may be fewer than asked
        index_t next = 0;
        for (index_t v = 0; v < nv; ++v) {
          start[static_cast<std::size_t>(v)] = next;
          for (std::size_t k = 0; k < team; ++k) {
            index_t& count = fill[k][static_cast<std::size_t>(v)];
            const index_t n = count;
            count = next;
            next += n;
          }
        }
        start[static_cast<std::size_t>(nv)] = next;
      }
#pragma omp for schedule(static)
      for (long i = 0; i < ntets; ++i)
        for (int f = 0; f < 4; ++f) {
          const FaceRecord r = face_record(static_cast<std::size_t>(i), f);
          faces[static_cast<std::size_t>(mine[static_cast<std::size_t>(r.v[0])]++)] = r;
        }
    }
  }
  const auto by_key_then_code = [](const FaceRecord& x, const FaceRecord& y) {
    return x < y || (x.same_face(y) && x.code < y.code);
  };
#pragma omp parallel for schedule(dynamic, 4096) if (nv >= kParallelMinItems)
  for (index_t v = 0; v < nv; ++v) std::sort(&faces[start[v]], &faces[start[v + 1]], by_key_then_code);

  rec_.resize(nt);
#pragma omp parallel for schedule(static) if (ntets >= kParallelMinItems)
  for (long t = 0; t < ntets; ++t)
    rec_[static_cast<std::size_t>(t)] = TetRecord{tets[static_cast<std::size_t>(t)], Tet{{-1, -1, -1, -1}}};
  std::vector<Tet>().swap(tets);
  std::size_t overshared = 0, mismatched = 0, boundary = 0;
  std::vector<char> offending(nt, 0);
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : overshared, mismatched, boundary) \
    if (nv >= kParallelMinItems)
  for (index_t v = 0; v < nv; ++v)
  for (std::size_t i = static_cast<std::size_t>(start[v]), last = static_cast<std::size_t>(start[v + 1]); i < last;) {
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
#pragma omp atomic write
        offending[sign[ta] < 0 ? ta : (sign[tb] < 0 ? tb : ta)] = 1;
      }
    } else {
      overshared += j - i;
    }
    i = j;
  }
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
  std::size_t nonmanifold_vertices = 0;
  index_t first_bad = std::numeric_limits<index_t>::max();
#pragma omp parallel reduction(+ : nonmanifold_vertices) reduction(min : first_bad) if (nv >= kParallelMinItems)
  {
    WalkMarks marks;
    std::vector<index_t> ball;
#pragma omp for schedule(dynamic, 4096)
    for (index_t v = 0; v < nv; ++v) {
      if (vertex_tet_[v] < 0) continue;
      vertex_ball(v, ball, marks);
      if (static_cast<index_t>(ball.size()) != incidence[v]) {
        ++nonmanifold_vertices;
        first_bad = std::min(first_bad, v);
      } else {
        vclass_[v] = classify_ball(v, ball);
      }
    }
  }
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

// ---------------------------------------------------------------------------
// Allocation
// ---------------------------------------------------------------------------

index_t TetMesh::new_tet(const Tet& vertices, index_t origin) {
  index_t t;
  if (!free_tets_.empty()) {
    t = free_tets_.back();
    free_tets_.pop_back();
    rec_[t].v = vertices;
    rec_[t].n = Tet{{-1, -1, -1, -1}};
    tet_origin_[t] = origin;
  } else {
    t = static_cast<index_t>(rec_.size());
    rec_.push_back(TetRecord{vertices, Tet{{-1, -1, -1, -1}}});
    tet_origin_.push_back(origin);
  }
  return t;
}

void TetMesh::delete_tet(index_t t) {
  rec_[t].v[0] = kInvalidIndex;
  free_tets_.push_back(t);
}

index_t TetMesh::new_vertex(const Vec3& p, const VertexStencil& origin, VertexClass c) {
  index_t v;
  if (!free_vertices_.empty()) {
    v = free_vertices_.back();
    free_vertices_.pop_back();
    points_[v] = p;
    vertex_origin_[v] = origin;
    vclass_[v] = c;
  } else {
    v = static_cast<index_t>(points_.size());
    points_.push_back(p);
    vertex_origin_.push_back(origin);
    vclass_.push_back(c);
    vertex_tet_.push_back(kInvalidIndex);
  }
  return v;
}

void TetMesh::delete_vertex(index_t v) {
  vertex_tet_[v] = kInvalidIndex;
  free_vertices_.push_back(v);
}

void TetMesh::set_face_region(index_t t, int f, index_t region) {
  if (rec_[t].n[f] < 0) rec_[t].n[f] = internal::boundary_code(region);
}

int TetMesh::local_index(index_t t, index_t v) const {
  if (t < 0) return -1;
  const Tet& T = rec_[t].v;
  for (int i = 0; i < 4; ++i)
    if (T[i] == v) return i;
  return -1;
}

// ---------------------------------------------------------------------------
// Topology queries
// ---------------------------------------------------------------------------

void TetMesh::vertex_ball(index_t v, std::vector<index_t>& out) const {
  out.clear();
  if (vertex_tet_[v] < 0) return;
  const std::uint16_t mark = next_tet_mark();
  walk_ball(v, out, tet_marks_.stamp.data(), mark);
}

void TetMesh::vertex_ball(index_t v, std::vector<index_t>& out, WalkMarks& marks) const {
  out.clear();
  if (vertex_tet_[v] < 0) return;
  const std::uint16_t mark = marks.next(rec_.size());
  walk_ball(v, out, marks.stamp.data(), mark);
}

index_t TetMesh::walk_ball(index_t v, std::vector<index_t>& out, std::uint16_t* marks, std::uint16_t mark,
                           index_t stop_at) const {
  // Breadth-first over the faces that contain v (those opposite the other
  // three vertices), marking visited tets.
  const index_t t0 = vertex_tet_[v];
  out.push_back(t0);
  marks[t0] = mark;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const index_t t = out[i];
    const TetRecord& R = rec_[t];
    if (stop_at >= 0 && (R.v[0] == stop_at || R.v[1] == stop_at || R.v[2] == stop_at || R.v[3] == stop_at))
      return t;
    for (int f = 0; f < 4; ++f) {
      if (R.v[f] == v) continue;
      const index_t code = R.n[f];
      if (code < 0) continue;
      const index_t n = code >> 2;
      if (marks[n] != mark) {
        marks[n] = mark;
        out.push_back(n);
      }
    }
  }
  return kInvalidIndex;
}

void TetMesh::vertex_neighbors(index_t v, std::vector<index_t>& out) const {
  vertex_ball(v, scratch_verts_);
  out.clear();
  for (index_t t : scratch_verts_)
    for (index_t w : rec_[t].v)
      if (w != v) out.push_back(w);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

bool TetMesh::edge_tet_without_walk(index_t a, index_t b, index_t hint, index_t* t) const {
  *t = kInvalidIndex;
  if (!vertex_alive(a) || !vertex_alive(b) || a == b) return true;
  const index_t ta = vertex_tet_[a], tb = vertex_tet_[b];
  if (tet_alive(hint) && local_index(hint, a) >= 0 && local_index(hint, b) >= 0)
    *t = hint;
  else if (local_index(ta, b) >= 0)
    *t = ta;
  else if (local_index(tb, a) >= 0)
    *t = tb;
  return *t >= 0;
}

index_t TetMesh::find_edge_tet(index_t a, index_t b, index_t hint) const {
  index_t t;
  if (edge_tet_without_walk(a, b, hint, &t)) return t;
  scratch_verts_.clear();
  if (vertex_tet_[a] < 0) return kInvalidIndex;
  const std::uint16_t mark = next_tet_mark();  // may grow tet_marks_
  return walk_ball(a, scratch_verts_, tet_marks_.stamp.data(), mark, b);
}

index_t TetMesh::find_edge_tet(index_t a, index_t b, index_t hint, WalkMarks& marks) const {
  index_t t;
  if (edge_tet_without_walk(a, b, hint, &t)) return t;
  thread_local std::vector<index_t> ball;
  ball.clear();
  if (vertex_tet_[a] < 0) return kInvalidIndex;
  const std::uint16_t mark = marks.next(rec_.size());
  return walk_ball(a, ball, marks.stamp.data(), mark, b);
}

bool TetMesh::edge_ring(index_t a, index_t b, std::vector<index_t>& ring, bool* on_boundary, index_t hint) const {
  return edge_ring_with_vertices(a, b, ring, scratch_ring_, on_boundary, hint);
}

bool TetMesh::edge_ring_with_vertices(index_t a, index_t b, std::vector<index_t>& ring,
                                      std::vector<index_t>& opposite, bool* on_boundary, index_t hint) const {
  ring.clear();
  opposite.clear();
  const index_t t0 = find_edge_tet(a, b, hint);
  if (t0 < 0) return false;
  // In a tet containing a and b with other vertices (x, y), crossing the face
  // opposite x leads to the next tet, which contains y and a new vertex.
  auto others = [&](index_t t, index_t* x, index_t* y) {
    int k = 0;
    index_t o[2] = {kInvalidIndex, kInvalidIndex};
    for (index_t w : rec_[t].v)
      if (w != a && w != b) o[k++] = w;
    *x = o[0];
    *y = o[1];
  };
  // Walk backwards first (crossing the face opposite y) to find an end of an
  // open ring, so the forward walk below lists the whole ring in order.
  index_t start = t0, x, y;
  others(t0, &x, &y);
  index_t start_x = x;  // first opposite vertex of the forward walk
  bool closed = false;
  {
    index_t t = t0, cx = x, cy = y;
    for (;;) {
      const index_t code = rec_[t].n[local_index(t, cy)];
      if (code < 0) {  // boundary: t is the first tet of the open ring
        start = t;
        start_x = cx;
        break;
      }
      const index_t n = code >> 2;
      if (n == t0) {
        closed = true;
        break;
      }
      // n contains a, b, cx and a new vertex w; going backwards, cy := cx.
      index_t nx, ny;
      others(n, &nx, &ny);
      const index_t w = (nx == cx) ? ny : nx;
      cy = cx;
      cx = w;
      t = n;
    }
  }
  if (closed) {
    start = t0;
    start_x = x;
  }
  // Forward: ring[i] has opposite vertices c[i], c[i + 1].
  index_t t = start, cx = start_x;
  for (;;) {
    index_t ox, oy;
    others(t, &ox, &oy);
    const index_t cy = (ox == cx) ? oy : ox;
    ring.push_back(t);
    opposite.push_back(cx);
    const index_t code = rec_[t].n[local_index(t, cx)];
    if (code < 0) {
      opposite.push_back(cy);
      break;
    }
    const index_t n = code >> 2;
    if (n == start) break;
    cx = cy;
    t = n;
  }
  if (on_boundary) *on_boundary = !closed;
  return true;
}

index_t TetMesh::find_face(index_t a, index_t b, index_t c, int* local_face) const {
  if (!vertex_alive(a) || !vertex_alive(b) || !vertex_alive(c)) return kInvalidIndex;
  vertex_ball(a, scratch_verts_);
  for (index_t t : scratch_verts_) {
    const int ib = local_index(t, b), ic = local_index(t, c);
    if (ib < 0 || ic < 0) continue;
    const int ia = local_index(t, a);
    const int f = 6 - ia - ib - ic;  // the remaining local index
    if (local_face) *local_face = f;
    return t;
  }
  return kInvalidIndex;
}

// ---------------------------------------------------------------------------
// Vertex classes (thesis Fig. 2.37)
// ---------------------------------------------------------------------------

bool TetMesh::is_curve_edge(index_t a, index_t b, index_t hint) const {
  bool boundary = false;
  thread_local std::vector<index_t> ring, c;
  if (!edge_ring_with_vertices(a, b, ring, c, &boundary, hint) || !boundary) return false;
  return open_ring_on_curve(ring, c);
}

bool TetMesh::open_ring_on_curve(const std::vector<index_t>& ring, const std::vector<index_t>& c) const {
  // An open ring starts with the boundary face opposite c[1] in ring[0] and
  // ends with the one opposite c[n - 1] in ring[n - 1] (c has n + 1 entries).
  const index_t first = ring.front(), last = ring.back();
  return face_region(first, local_index(first, c[1])) != face_region(last, local_index(last, c[c.size() - 2]));
}

VertexClass TetMesh::classify_ball(index_t v, const std::vector<index_t>& ball) const {
  // Regions of the boundary faces around v, and the curve edges at v.
  index_t region0 = kInvalidIndex - 1;  // "none seen yet"
  bool on_bnd = false, several_regions = false;
  for (index_t t : ball) {
    const Tet& T = rec_[t].v;
    for (int f = 0; f < 4; ++f) {
      if (T[f] == v || rec_[t].n[f] >= 0) continue;
      const index_t r = face_region(t, f);
      if (!on_bnd) {
        on_bnd = true;
        region0 = r;
      } else if (r != region0) {
        several_regions = true;
      }
    }
  }
  if (!on_bnd) return VertexClass::Inner;
  if (!several_regions) return VertexClass::Surface;
  // Count curve edges: boundary edges (v, w) whose two faces differ in region.
  int curve_edges = 0;
  for (index_t t : ball) {
    const Tet& T = rec_[t].v;
    for (int f = 0; f < 4; ++f) {
      if (T[f] == v || rec_[t].n[f] >= 0) continue;
      // Boundary face f of t contains v; its two edges at v go to the other
      // two face vertices. Each boundary edge is seen from its two faces:
      // count it from the face with the smaller code to avoid doubles.
      const index_t r = face_region(t, f);
      for (int k = 0; k < 3; ++k) {
        const index_t w = T[kTetFace[f][k]];
        if (w == v) continue;
        const int other = internal::boundary_face_across_edge(*this, t, f, v, w);
        const index_t ot = other >> 2, of = other & 3;
        if (face_region(ot, of) != r && 4 * t + f < other) ++curve_edges;
      }
    }
  }
  return curve_edges == 2 ? VertexClass::Curve : VertexClass::Corner;
}

void TetMesh::classify_vertices() {
  const index_t n = vertex_slots();
#pragma omp parallel if (n >= kParallelMinItems)
  {
    WalkMarks marks;
    std::vector<index_t> ball;
#pragma omp for schedule(dynamic, 4096)
    for (index_t v = 0; v < n; ++v) {
      if (!vertex_alive(v)) {
        vclass_[v] = VertexClass::Inner;
        continue;
      }
      vertex_ball(v, ball, marks);
      vclass_[v] = classify_ball(v, ball);
    }
  }
}

// ---------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------

int TetMesh::orientation(index_t t) const {
  const Tet& T = rec_[t].v;
  return orient3d_sign(points_[T[0]], points_[T[1]], points_[T[2]], points_[T[3]]);
}

OpStatus TetMesh::move_vertex(index_t v, const Vec3& p) {
  if (!vertex_alive(v) || !p.allFinite()) return OpStatus::InvalidArgument;
  vertex_ball(v, scratch_ball_);
  const OpStatus s = move_vertex_in_ball(v, p, scratch_ball_);
  if (s == OpStatus::Ok) touched_ = scratch_ball_;
  return s;
}

OpStatus TetMesh::move_vertex_in_ball(index_t v, const Vec3& p, const std::vector<index_t>& ball) {
  if (!vertex_alive(v) || !p.allFinite()) return OpStatus::InvalidArgument;
  for (index_t t : ball) {
    const Tet& T = rec_[t].v;
    const Vec3* q[4];
    for (int i = 0; i < 4; ++i) q[i] = T[i] == v ? &p : &points_[T[i]];
    if (orient3d_sign(*q[0], *q[1], *q[2], *q[3]) <= 0) return OpStatus::Inverted;
  }
  points_[v] = p;
  return OpStatus::Ok;
}

// ---------------------------------------------------------------------------
// Cavity replacement: the one mechanism behind every local operation.
// ---------------------------------------------------------------------------

void TetMesh::replace_tets(const std::vector<index_t>& old_tets, const std::vector<Tet>& new_tets,
                           const std::vector<index_t>& new_origins, index_t rename_from, index_t rename_to) {
  using internal::FaceSlot;
  std::vector<FaceSlot>& slots = internal::face_slot_scratch();
  slots.clear();
  const std::uint16_t in_cavity = next_tet_mark();
  std::vector<std::uint16_t>& mark = tet_marks_.stamp;
  for (index_t t : old_tets) mark[t] = in_cavity;
  auto make_slot = [](index_t x, index_t y, index_t z, index_t code, index_t is_new) {
    FaceSlot fs{{x, y, z}, code, is_new};
    internal::sort3_ids(fs.v);
    return fs;
  };
  // Outer faces of the cavity, with the renaming applied.
  for (index_t t : old_tets) {
    const TetRecord& R = rec_[t];
    for (int f = 0; f < 4; ++f) {
      const index_t code = R.n[f];
      if (code >= 0 && mark[code >> 2] == in_cavity) continue;  // inside the cavity
      index_t w[3];
      for (int k = 0; k < 3; ++k) {
        w[k] = R.v[kTetFace[f][k]];
        // Outer tets survive: let their vertices point at them for now.
        if (code >= 0 && w[k] != rename_from) vertex_tet_[w[k]] = code >> 2;
        if (w[k] == rename_from) w[k] = rename_to;
      }
      slots.push_back(make_slot(w[0], w[1], w[2], code, 0));
    }
  }
  for (index_t t : old_tets) delete_tet(t);
  touched_.clear();
  for (std::size_t i = 0; i < new_tets.size(); ++i) {
    const Tet& T = new_tets[i];
    const index_t t = new_tet(T, new_origins[i]);
    touched_.push_back(t);
    for (index_t w : T) vertex_tet_[w] = t;
    for (int f = 0; f < 4; ++f)
      slots.push_back(make_slot(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]], 4 * t + f, 1));
  }

  // Every face key appears twice: two new faces (inside the new tets), a new
  // face and an outer face (cavity boundary), or two outer faces (a vanished
  // tet between them, zipped). A key seen once is a boundary face subdivided
  // by a split (outer (a, b, x) -> new (a, m, x) and (m, b, x)). Pairs are
  // found with a small open-addressing table (cavities hold tens of faces).
  thread_local std::vector<std::int32_t> table;
  thread_local std::vector<char> matched;
  std::size_t capacity = 64;
  while (capacity < 2 * slots.size()) capacity *= 2;
  table.assign(capacity, -1);
  matched.assign(slots.size(), 0);
  const std::size_t mask = capacity - 1;
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const FaceSlot& fs = slots[i];
    std::size_t h = (static_cast<std::uint32_t>(fs.v[0]) * 2654435761u ^ static_cast<std::uint32_t>(fs.v[1]) * 40503u ^
                     static_cast<std::uint32_t>(fs.v[2]) * 2246822519u) >> 4;
    for (h &= mask;; h = (h + 1) & mask) {
      const std::int32_t e = table[h];
      if (e < 0) {
        table[h] = static_cast<std::int32_t>(i);
        break;
      }
      if (!matched[e] && slots[e].same_face(fs)) {
        link_faces(slots[e], fs);
        matched[e] = matched[i] = 1;
        break;
      }
    }
  }
  // A subdivided boundary face passes its region to its pieces: the piece
  // shares two vertices with it (the third is the new vertex).
  for (std::size_t i = 0; i < slots.size(); ++i) {
    if (matched[i] || !slots[i].is_new) continue;
    for (std::size_t j = 0; j < slots.size(); ++j) {
      if (matched[j] || slots[j].is_new) continue;
      const FaceSlot& n = slots[i];
      const FaceSlot& o = slots[j];
      int shared = 0;
      for (int k = 0; k < 3; ++k) shared += (n.v[k] == o.v[0] || n.v[k] == o.v[1] || n.v[k] == o.v[2]);
      if (shared == 2) {
        rec_[n.code >> 2].n[n.code & 3] = o.code;
        break;
      }
    }
  }
}

void TetMesh::link_faces(const internal::FaceSlot& p, const internal::FaceSlot& q) {
  const index_t cp = p.code, cq = q.code;
  if (p.is_new && q.is_new) {
    rec_[cp >> 2].n[cp & 3] = cq;
    rec_[cq >> 2].n[cq & 3] = cp;
  } else if (p.is_new || q.is_new) {
    const index_t cn = p.is_new ? cp : cq, co = p.is_new ? cq : cp;
    rec_[cn >> 2].n[cn & 3] = co;
    if (co >= 0) rec_[co >> 2].n[co & 3] = cn;
  } else if (cp >= 0 && cq >= 0) {
    rec_[cp >> 2].n[cp & 3] = cq;
    rec_[cq >> 2].n[cq & 3] = cp;
  } else if (cp >= 0) {
    rec_[cp >> 2].n[cp & 3] = cq;  // takes the boundary code (region) over
  } else if (cq >= 0) {
    rec_[cq >> 2].n[cq & 3] = cp;
  }
}

// ---------------------------------------------------------------------------
// Output and checks
// ---------------------------------------------------------------------------

CompactMesh TetMesh::compact() const {
  CompactMesh out;
  out.vertex_map.assign(points_.size(), kInvalidIndex);
  for (index_t v = 0; v < vertex_slots(); ++v) {
    if (!vertex_alive(v)) continue;
    out.vertex_map[v] = static_cast<index_t>(out.points.size());
    out.points.push_back(points_[v]);
    out.vertex_classes.push_back(vclass_[v]);
    out.vertex_origin.push_back(vertex_origin_[v]);
  }
  const std::size_t nt = live_tets();
  out.tets.reserve(nt);
  out.face_regions.reserve(nt);
  out.tet_origin.reserve(nt);
  for (index_t t = 0; t < tet_slots(); ++t) {
    if (!tet_alive(t)) continue;
    Tet T, R;
    for (int i = 0; i < 4; ++i) {
      T[i] = out.vertex_map[rec_[t].v[i]];
      R[i] = face_region(t, i);
    }
    out.tets.push_back(T);
    out.face_regions.push_back(R);
    out.tet_origin.push_back(tet_origin_[t]);
  }
  return out;
}

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
#pragma omp parallel for schedule(static) if (nv >= kParallelMinItems)
  for (index_t v = 0; v < nv; ++v) {
    if (!vertex_alive(v)) continue;
    const Vec3 u = (points_[v] - lo).cwiseProduct(scale);
    vkeys[v] = {spread(static_cast<std::uint64_t>(u.x())) | spread(static_cast<std::uint64_t>(u.y())) << 1 |
                    spread(static_cast<std::uint64_t>(u.z())) << 2,
                v};
  }
  std::sort(vkeys.begin(), vkeys.end());
  while (!vkeys.empty() && vkeys.back().second == kInvalidIndex) vkeys.pop_back();
  const index_t new_nv = static_cast<index_t>(vkeys.size());
  std::vector<index_t> vmap(static_cast<std::size_t>(nv), kInvalidIndex);
  for (index_t i = 0; i < new_nv; ++i) vmap[vkeys[i].second] = i;
  // Tets by their lowest new vertex id, then old id (a counting sort).
  std::vector<index_t> first(static_cast<std::size_t>(nt), kInvalidIndex);
  std::vector<index_t> start(static_cast<std::size_t>(new_nv) + 1, 0);
#pragma omp parallel for schedule(static) if (nt >= kParallelMinItems)
  for (index_t t = 0; t < nt; ++t) {
    if (!tet_alive(t)) continue;
    const Tet& T = rec_[t].v;
    first[t] = std::min({vmap[T[0]], vmap[T[1]], vmap[T[2]], vmap[T[3]]});
#pragma omp atomic
    ++start[first[t] + 1];
  }
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
#pragma omp parallel for schedule(static) if (new_nv >= kParallelMinItems)
  for (index_t i = 0; i < new_nv; ++i) {
    const index_t v = vkeys[i].second;
    points[i] = points_[v];
    vclass[i] = vclass_[v];
    vorigin[i] = vertex_origin_[v];
    vtet[i] = tmap[vertex_tet_[v]];
  }
  // Not value-initialised: the pages are first touched by the parallel
  // writes below (x3 benchmark, the first sort at 1.2M tets: 0.42 -> 0.24 s
  // with the copies back in parallel).
  const std::unique_ptr<TetRecord[]> rec(new TetRecord[static_cast<std::size_t>(new_nt)]);
  const std::unique_ptr<index_t[]> torigin(new index_t[static_cast<std::size_t>(new_nt)]);
#pragma omp parallel for schedule(static) if (new_nt >= kParallelMinItems)
  for (index_t i = 0; i < new_nt; ++i) {
    const index_t t = order[i];
    for (int k = 0; k < 4; ++k) {
      rec[i].v[k] = vmap[rec_[t].v[k]];
      const index_t code = rec_[t].n[k];
      rec[i].n[k] = code >= 0 ? (tmap[code >> 2] << 2 | (code & 3)) : code;  // boundary codes hold the region
    }
    torigin[i] = tet_origin_[t];
  }
  // Copied back rather than swapped: the old arrays keep their capacity, so
  // the next edits grow them without reallocating (0.1 s at 1M tets). In
  // parallel, into arrays no longer than before (nothing to fill).
  points_.resize(nnv);
  vclass_.resize(nnv);
  vertex_origin_.resize(nnv);
  vertex_tet_.resize(nnv);
#pragma omp parallel for schedule(static) if (new_nv >= kParallelMinItems)
  for (index_t i = 0; i < new_nv; ++i) {
    points_[static_cast<std::size_t>(i)] = points[static_cast<std::size_t>(i)];
    vclass_[static_cast<std::size_t>(i)] = vclass[static_cast<std::size_t>(i)];
    vertex_origin_[static_cast<std::size_t>(i)] = vorigin[static_cast<std::size_t>(i)];
    vertex_tet_[static_cast<std::size_t>(i)] = vtet[static_cast<std::size_t>(i)];
  }
  rec_.resize(static_cast<std::size_t>(new_nt));
  tet_origin_.resize(static_cast<std::size_t>(new_nt));
#pragma omp parallel for schedule(static) if (new_nt >= kParallelMinItems)
  for (index_t i = 0; i < new_nt; ++i) {
    rec_[static_cast<std::size_t>(i)] = rec[static_cast<std::size_t>(i)];
    tet_origin_[static_cast<std::size_t>(i)] = torigin[static_cast<std::size_t>(i)];
  }
  free_tets_.clear();
  free_vertices_.clear();
  tet_marks_.reset(rec_.size());
  link_stamps_.reset(points_.size());
  touched_.clear();
  return vmap;
}

std::size_t TetMesh::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(points_) + bytes(rec_) + bytes(vertex_tet_) + bytes(vclass_) +
         bytes(tet_origin_) + bytes(vertex_origin_) + bytes(free_tets_) + bytes(free_vertices_) +
         bytes(tet_marks_.stamp) + bytes(link_stamps_.stamp) + bytes(scratch_ring_) + bytes(scratch_verts_) +
         bytes(scratch_ball_) + bytes(scratch_ball2_) + bytes(scratch_new_) + bytes(scratch_origin_) + bytes(touched_);
}

Status TetMesh::check_consistency() const {
  std::ostringstream err;
  std::size_t errors = 0;
  auto note = [&](const std::string& m) {
    if (errors++ < 10) err << m << "\n";
  };
  for (index_t t = 0; t < tet_slots(); ++t) {
    if (!tet_alive(t)) continue;
    const Tet& T = rec_[t].v;
    for (int i = 0; i < 4; ++i) {
      if (!vertex_alive(T[i])) note("tet " + std::to_string(t) + " uses dead vertex " + std::to_string(T[i]));
      for (int j = 0; j < i; ++j)
        if (T[i] == T[j]) note("tet " + std::to_string(t) + " repeats a vertex");
    }
    const int o = orientation(t);
    if (o < 0 || (o == 0 && !allow_inverted_))
      if (!allow_inverted_) note("tet " + std::to_string(t) + " is not positively oriented");
    for (int f = 0; f < 4; ++f) {
      const index_t code = rec_[t].n[f];
      if (code < 0) continue;
      const index_t n = code >> 2, g = code & 3;
      if (!tet_alive(n)) {
        note("tet " + std::to_string(t) + " face " + std::to_string(f) + " points to dead tet");
        continue;
      }
      if (rec_[n].n[g] != 4 * t + f) note("adjacency not symmetric at tet " + std::to_string(t));
      index_t a[3], b[3];
      for (int k = 0; k < 3; ++k) {
        a[k] = T[kTetFace[f][k]];
        b[k] = rec_[n].v[kTetFace[g][k]];
      }
      const bool oa = internal::sort3_parity(a), ob = internal::sort3_parity(b);
      if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2])
        note("tet " + std::to_string(t) + " face " + std::to_string(f) + " does not match its neighbour's face");
      else if (oa == ob)
        note("tet " + std::to_string(t) + " and its neighbour disagree on orientation");
    }
  }
  std::vector<index_t> ball;
  for (index_t v = 0; v < vertex_slots(); ++v) {
    if (!vertex_alive(v)) continue;
    const index_t t = vertex_tet_[v];
    if (!tet_alive(t) || local_index(t, v) < 0) note("vertex " + std::to_string(v) + " has a stale incident tet");
  }
  // Every live tet's vertices reach it through their ball walk.
  std::vector<index_t> count(points_.size(), 0);
  for (index_t t = 0; t < tet_slots(); ++t)
    if (tet_alive(t))
      for (index_t w : rec_[t].v) ++count[w];
  for (index_t v = 0; v < vertex_slots(); ++v) {
    if (!vertex_alive(v)) {
      if (count[v]) note("dead vertex " + std::to_string(v) + " is used by tets");
      continue;
    }
    if (count[v] == 0) note("vertex " + std::to_string(v) + " is alive but used by no tet");
    vertex_ball(v, ball);
    if (static_cast<index_t>(ball.size()) != count[v])
      note("ball walk of vertex " + std::to_string(v) + " misses tets");
  }
  for (index_t t : free_tets_)
    if (tet_alive(t)) note("free tet " + std::to_string(t) + " is alive");
  for (index_t v : free_vertices_)
    if (vertex_alive(v)) note("free vertex " + std::to_string(v) + " is alive");
  if (errors) return Status::failure(std::to_string(errors) + " inconsistencies:\n" + err.str());
  return Status::success();
}

}  // namespace femorph
