// Flips 2-3, 3-2 and 4-4 under the three conditions of thesis 2.6.5.4.
#include "improve/improve_tets_by_flips.h"

#include "common/parallel.h"
#include "geometry/predicates.h"
#include "improve/locally_delaunay.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <deque>
#include <limits>
#include <utility>

namespace femorph {

namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();

struct Candidate {
  int kind = 0;  // 0: flip 2-3 of face f of t; 1: flip 3-2 of (a, b); 2: flip 4-4 of (a, b)
  index_t t = kInvalidIndex;
  int f = 0;     // face (2-3) or diagonal (4-4)
  index_t a = kInvalidIndex, b = kInvalidIndex;
  double quality = kNone;
};

class FlipEvaluator {
 public:
  FlipEvaluator(TetMesh& mesh, const FlipImproveOptions& options) : mesh_(mesh), options_(options) {}

  double stretch(index_t t) const {
    const Tet& T = mesh_.tet(t);
    return tet_stretch(mesh_.point(T[0]), mesh_.point(T[1]), mesh_.point(T[2]), mesh_.point(T[3]));
  }

  bool allowed(const Tet& T) const {
    if (options_.vertex_mask.empty()) return true;
    for (index_t v : T)
      if (static_cast<std::size_t>(v) < options_.vertex_mask.size() && options_.vertex_mask[v]) return true;
    return false;
  }

  /// Minimum stretch of `fresh` (orientation repaired in place) if the flip
  /// old -> fresh meets the conditions of 2.6.5.4, else kNone.
  double evaluate(const std::vector<index_t>& old, std::vector<Tet>& fresh) const {
    double old_min = std::numeric_limits<double>::infinity();
    for (index_t t : old) {
      if (!allowed(mesh_.tet(t))) return kNone;
      old_min = std::min(old_min, known_stretch(t));
    }
    // Condition 3: the minimum quality rises. Orientation is checked exactly.
    double new_min = std::numeric_limits<double>::infinity();
    for (Tet& T : fresh) {
      if (!allowed(T)) return kNone;
      const int s = orient3d_sign(mesh_.point(T[0]), mesh_.point(T[1]), mesh_.point(T[2]), mesh_.point(T[3]));
      if (s == 0) return kNone;
      if (s < 0) std::swap(T[2], T[3]);
      new_min = std::min(new_min, tet_stretch(mesh_.point(T[0]), mesh_.point(T[1]), mesh_.point(T[2]), mesh_.point(T[3])));
    }
    if (!(new_min > old_min + options_.min_gain)) return kNone;
    if (!options_.delaunay_conditions) return new_min;
    // Condition 1: some old tet is not Delaunay.
    bool some_bad = false;
    for (index_t t : old) some_bad = some_bad || !locally_delaunay(mesh_, t);
    if (!some_bad) return kNone;
    // Condition 2: every new tet is Delaunay with respect to the cavity's
    // vertices and the opposite vertices of its outer neighbours.
    points_.clear();
    for (index_t t : old) {
      const Tet& T = mesh_.tet(t);
      for (int f = 0; f < 4; ++f) {
        points_.push_back(T[f]);
        const index_t code = mesh_.adjacency(t, f);
        if (code >= 0 && std::find(old.begin(), old.end(), code >> 2) == old.end())
          points_.push_back(mesh_.tet(code >> 2)[code & 3]);
      }
    }
    std::sort(points_.begin(), points_.end());
    points_.erase(std::unique(points_.begin(), points_.end()), points_.end());
    for (const Tet& T : fresh)
      for (index_t p : points_) {
        if (p == T[0] || p == T[1] || p == T[2] || p == T[3]) continue;
        if (insphere_sign(mesh_.point(T[0]), mesh_.point(T[1]), mesh_.point(T[2]), mesh_.point(T[3]), mesh_.point(p)) > 0)
          return kNone;
      }
    return new_min;
  }

  /// Every admissible flip around tet t, best first.
  void candidates(index_t t, std::vector<Candidate>& out) {
    out.clear();
    known_.clear();
    const Tet T = mesh_.tet(t);
    if (!allowed(T)) return;  // every flip of t replaces t
    // Flip 2-3 of each interior face: (a, b, c) | d, e -> three tets on (d, e).
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh_.adjacency(t, f);
      if (code < 0) continue;
      const index_t n = code >> 2, e = mesh_.tet(n)[code & 3], d = T[f];
      const index_t a = T[kTetFace[f][0]], b = T[kTetFace[f][1]], c = T[kTetFace[f][2]];
      old_ = {t, n};
      fresh_ = {Tet{{a, b, d, e}}, Tet{{b, c, d, e}}, Tet{{c, a, d, e}}};
      const double q = evaluate(old_, fresh_);
      if (q > kNone) out.push_back({0, t, f, kInvalidIndex, kInvalidIndex, q});
    }
    // Flips 3-2 and 4-4 of each edge.
    for (const auto& e : kTetEdge) {
      const index_t a = T[e[0]], b = T[e[1]];
      if (!closed_ring_up_to_4(a, b, t)) continue;
      const std::size_t n = ring_.size();
      if (n != 3 && n != 4) continue;
      // c[i]: the ring vertex shared by ring[i - 1] and ring[i] (ring[i]
      // holds c[i] and c[i + 1], TetMesh's convention).
      index_t c[4];
      for (std::size_t i = 0; i < n; ++i) {
        const Tet& P = mesh_.tet(ring_[(i + n - 1) % n]);
        c[i] = kInvalidIndex;
        for (index_t w : mesh_.tet(ring_[i]))
          if (w != a && w != b && std::find(P.begin(), P.end(), w) != P.end()) c[i] = w;
      }
      if (n == 3) {
        fresh_ = {Tet{{c[0], c[1], c[2], a}}, Tet{{c[0], c[1], c[2], b}}};
        const double q = evaluate(ring_, fresh_);
        if (q > kNone) out.push_back({1, t, 0, a, b, q});
      } else {
        for (int k = 0; k < 2; ++k) {
          fresh_ = {Tet{{a, c[k], c[k + 1], c[k + 2]}}, Tet{{b, c[k], c[k + 1], c[k + 2]}},
                    Tet{{a, c[k + 2], c[(k + 3) % 4], c[k]}}, Tet{{b, c[k + 2], c[(k + 3) % 4], c[k]}}};
          const double q = evaluate(ring_, fresh_);
          if (q > kNone) out.push_back({2, t, k, a, b, q});
        }
      }
    }
    std::stable_sort(out.begin(), out.end(), [](const Candidate& x, const Candidate& y) { return x.quality > y.quality; });
  }

 private:
  /// ring_ = the tets around interior edge (a, b) of tet t when they are
  /// three or four, in TetMesh::edge_ring()'s order from t (the 4-4 flip's
  /// diagonal index refers to it); false otherwise. The walk stops at the
  /// fifth tet or a boundary face: most rings are longer, and edge_ring()
  /// would walk them whole, twice.
  bool closed_ring_up_to_4(index_t a, index_t b, index_t t) {
    ring_.clear();
    const auto others = [&](index_t u, index_t* x, index_t* y) {
      int k = 0;
      index_t o[2] = {kInvalidIndex, kInvalidIndex};
      for (const index_t w : mesh_.tet(u))
        if (w != a && w != b && k < 2) o[k++] = w;
      *x = o[0];
      *y = o[1];
    };
    index_t u = t, cx, cy;
    others(t, &cx, &cy);
    for (;;) {
      index_t ox, oy;
      others(u, &ox, &oy);
      cy = ox == cx ? oy : ox;
      ring_.push_back(u);
      if (ring_.size() > 4) return false;
      const index_t code = mesh_.adjacency(u, mesh_.local_index(u, cx));
      if (code < 0) return false;  // a boundary edge
      u = code >> 2;
      if (u == t) return ring_.size() >= 3;
      cx = cy;
    }
  }

  /// stretch(t), each tet computed once per candidates() call: t and its
  /// neighbours are in most of the ten flips it tries.
  double known_stretch(index_t t) const {
    for (const auto& [u, q] : known_)
      if (u == t) return q;
    const double q = stretch(t);
    known_.emplace_back(t, q);
    return q;
  }

  TetMesh& mesh_;
  const FlipImproveOptions& options_;
  mutable std::vector<std::pair<index_t, double>> known_;
  std::vector<index_t> ring_, old_;
  std::vector<Tet> fresh_;
  mutable std::vector<index_t> points_;
};

}  // namespace

FlipImproveReport improve_tets_by_flips(TetMesh& mesh, const FlipImproveOptions& options) {
  FlipImproveReport report;
  // One evaluator (scratch) per thread: candidates are evaluated read only.
  std::vector<FlipEvaluator> evals(static_cast<std::size_t>(parallel_threads()), FlipEvaluator(mesh, options));
  FlipEvaluator& eval = evals[0];
  const std::size_t max_visits = options.max_visits ? options.max_visits : 20 * mesh.live_tets() + 1;
  std::deque<index_t> queue;
  std::vector<std::uint8_t> queued(mesh.tet_slots(), 0);
  auto push = [&](index_t t) {
    if (static_cast<std::size_t>(t) >= queued.size()) queued.resize(static_cast<std::size_t>(t) + 1, 0);
    if (queued[t] || !eval.allowed(mesh.tet(t)) || eval.stretch(t) >= options.quality_threshold) return;
    queued[t] = 1;
    queue.push_back(t);
  };
  // Queued with a stride: neighbouring slots hold neighbouring tets
  // (TetMesh::sort_spatially), and a batch of neighbours mostly conflicts.
  // The stretches first, in parallel and in slot order (a serial scan in
  // stride order misses the cache on every tet).
  constexpr index_t kStride = 61;
  {
    const long slots = mesh.tet_slots();
    std::vector<std::uint8_t> poor(static_cast<std::size_t>(slots), 0);
    // A tet without a vertex of the mask has no flip (the rest of the mesh
    // of a local run): not queued.
    parallel_for(slots, [&](long t) {
      const index_t k = static_cast<index_t>(t);
      poor[static_cast<std::size_t>(t)] = mesh.tet_alive(k) && eval.allowed(mesh.tet(k)) &&
                                          !(eval.stretch(k) >= options.quality_threshold);
    });
    for (index_t s = 0; s < kStride; ++s)
      for (index_t t = s; t < slots; t += kStride)
        if (poor[static_cast<std::size_t>(t)]) {
          queued[t] = 1;
          queue.push_back(t);
        }
  }

  // Beyond the thesis: the queue is taken in batches, whose candidates are
  // evaluated in parallel and applied in queue order. A flip changes only
  // tets made of the vertices it marks, and every tet a tet's evaluation
  // reads shares two vertices with it, so a tet with no marked vertex was
  // evaluated on the mesh as it is; one with a marked vertex goes back into
  // the queue. The batches do not depend on the number of threads.
  constexpr std::size_t kBatch = 64;
  std::vector<index_t> batch;
  std::vector<std::vector<Candidate>> cands(kBatch);
  std::vector<std::uint32_t> changed;
  std::uint32_t batch_id = 0;
  while (!queue.empty()) {
    batch.clear();
    while (batch.size() < kBatch && !queue.empty()) {
      if (report.visits >= max_visits) break;
      ++report.visits;
      const index_t t = queue.front();
      queue.pop_front();
      queued[t] = 0;
      if (!mesh.tet_alive(t) || eval.stretch(t) >= options.quality_threshold) continue;
      batch.push_back(t);
    }
    if (batch.empty()) {
      if (report.visits >= max_visits && !queue.empty()) report.exhausted = true;
      break;
    }
    const long count = static_cast<long>(batch.size());
    parallel_for_worker(
        count,
        [&](long i, int worker) {
          evals[static_cast<std::size_t>(worker)].candidates(batch[static_cast<std::size_t>(i)],
                                                             cands[static_cast<std::size_t>(i)]);
        },
        16, 4);
    ++batch_id;
    if (changed.size() < static_cast<std::size_t>(mesh.vertex_slots()))
      changed.resize(static_cast<std::size_t>(mesh.vertex_slots()), 0);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const index_t t = batch[i];
      if (!mesh.tet_alive(t)) continue;
      const Tet& T = mesh.tet(t);
      if (std::any_of(T.begin(), T.end(), [&](index_t v) { return changed[static_cast<std::size_t>(v)] == batch_id; })) {
        push(t);  // evaluated on a neighbourhood that has changed since
        continue;
      }
      for (const Candidate& cand : cands[i]) {
        OpStatus s = OpStatus::InvalidArgument;
        switch (cand.kind) {
          case 0: s = mesh.flip_23(cand.t, cand.f); break;
          case 1: s = mesh.flip_32(cand.a, cand.b, cand.t); break;
          default: s = mesh.flip_44(cand.a, cand.b, cand.f, cand.t); break;
        }
        if (s != OpStatus::Ok) continue;
        (cand.kind == 0 ? report.flips_23 : cand.kind == 1 ? report.flips_32 : report.flips_44)++;
        const std::vector<index_t>& touched = mesh.touched_tets();  // push() does not change the mesh
        for (const index_t n : touched)
          for (const index_t v : mesh.tet(n)) changed[static_cast<std::size_t>(v)] = batch_id;
        for (const index_t n : touched) push(n);
        break;
      }
    }
    if (report.visits >= max_visits && !queue.empty()) {
      report.exhausted = true;
      break;
    }
  }
  return report;
}

}  // namespace femorph
