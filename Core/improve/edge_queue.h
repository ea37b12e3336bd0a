// The heaps of the mesh density control, thesis 2.6.3 Fig. 2.40 (c): steps 1
// and 4 put the long (short) edges into a max-heap (min-heap) by length.
#pragma once

#include "common/types.h"

#include <algorithm>
#include <cstddef>
#include <queue>
#include <utility>
#include <vector>

namespace femorph {

/// An edge (a < b) in the split or the collapse heap.
struct HeapEdge {
  double length;
  index_t a, b;
  /// What the pass keeps with the entry: the split pass, a tet that held the
  /// edge when it was found (a hint for its ring); the collapse pass, its
  /// clock when the entry was made (an entry is current while neither end
  /// has moved since).
  index_t tag = kInvalidIndex;
};

/// Heap orders as std::priority_queue takes them, the ties broken by the
/// ends so that the order of pops never depends on the heap's layout.
struct Longer {
  bool operator()(const HeapEdge& x, const HeapEdge& y) const {
    if (x.length != y.length) return x.length < y.length;
    return x.a != y.a ? x.a > y.a : x.b > y.b;
  }
};
struct Shorter {
  bool operator()(const HeapEdge& x, const HeapEdge& y) const {
    if (x.length != y.length) return x.length > y.length;
    return x.a != y.a ? x.a > y.a : x.b > y.b;
  }
};

/// A heap (`Lower` as std::priority_queue takes it) made of the scan's edges
/// sorted once plus a heap for the edges pushed later: the same order of
/// pops as one std::priority_queue of all of them (entries equal under
/// `Lower` may come in either order), without the cache misses of sifting
/// the scan's edges.
template <class Lower>
class EdgeQueue {
 public:
  explicit EdgeQueue(std::vector<HeapEdge> scanned) : run_(std::move(scanned)) {
    std::sort(run_.begin(), run_.end(), [](const HeapEdge& x, const HeapEdge& y) { return Lower()(y, x); });
  }
  bool empty() const { return next_ == run_.size() && later_.empty(); }
  /// The first entry in heap order, removed; the queue must not be empty.
  HeapEdge pop() {
    if (next_ < run_.size() && (later_.empty() || !Lower()(run_[next_], later_.top()))) return run_[next_++];
    const HeapEdge top = later_.top();
    later_.pop();
    return top;
  }
  void push(const HeapEdge& e) { later_.push(e); }

 private:
  std::vector<HeapEdge> run_;
  std::size_t next_ = 0;
  std::priority_queue<HeapEdge, std::vector<HeapEdge>, Lower> later_;
};
using MaxEdgeQueue = EdgeQueue<Longer>;
using MinEdgeQueue = EdgeQueue<Shorter>;

}  // namespace femorph
