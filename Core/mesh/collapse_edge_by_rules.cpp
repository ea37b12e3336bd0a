// Edge collapse that preserves the shape, thesis 2.6.1.3 Fig. 2.37:
// forbidden edges (A)-(C) and the position rules (D)-(G).
#include "mesh/tet_mesh.h"

namespace femorph {

CollapsePlan TetMesh::plan_collapse_by_rules(index_t a, index_t b, index_t hint) const {
  CollapsePlan plan;
  bool boundary_edge = false;
  thread_local std::vector<index_t> ring, c;
  if (!edge_ring_with_vertices(a, b, ring, c, &boundary_edge, hint)) {
    plan.status = OpStatus::InvalidArgument;
    return plan;
  }
  const VertexClass ca = vclass_[a], cb = vclass_[b];
  const bool on_curve = boundary_edge && open_ring_on_curve(ring, c);
  auto feature_or_curve = [](VertexClass c) { return c == VertexClass::Curve || c == VertexClass::Corner; };
  auto forbid = [&plan] {
    plan.status = OpStatus::ForbiddenByRule;
    return plan;
  };
  // (A) an edge joining two feature (corner) vertices.
  if (ca == VertexClass::Corner && cb == VertexClass::Corner) return forbid();
  // (B) an edge joining two boundary-edge vertices that does not lie on a
  //     boundary edge segment (a curve).
  if (feature_or_curve(ca) && feature_or_curve(cb) && !on_curve) return forbid();
  // (C) an interior edge joining two vertices on the surface (of any class:
  //     collapsing it would pinch the part).
  if (!boundary_edge && ca != VertexClass::Inner && cb != VertexClass::Inner) return forbid();

  // (D) keep a feature vertex; (E) keep a boundary-edge vertex when the edge
  // leaves its curve; (F) keep the surface vertex of an interior edge.
  // In each case the more constrained class wins, and ties are (G).
  auto keep_first = [&](index_t k, index_t r) {
    plan.keep = k;
    plan.remove = r;
    plan.position = points_[k];
    return plan;
  };
  if (ca > cb) return keep_first(a, b);
  if (cb > ca) return keep_first(b, a);
  // (G) equal classes (inner-inner, surface-surface on the surface, curve-
  // curve along the curve): the midpoint.
  plan.keep = a;
  plan.remove = b;
  plan.position = 0.5 * (points_[a] + points_[b]);
  return plan;
}

OpStatus TetMesh::collapse_edge_by_rules(index_t a, index_t b, index_t* kept, index_t hint) {
  const CollapsePlan plan = plan_collapse_by_rules(a, b, hint);
  if (plan.status != OpStatus::Ok) return plan.status;
  const OpStatus status = collapse_edge(Keep{plan.keep}, Remove{plan.remove}, &plan.position);
  if (status == OpStatus::Ok && kept) *kept = plan.keep;
  return status;
}

}  // namespace femorph
