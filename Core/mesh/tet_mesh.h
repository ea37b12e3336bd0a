// TetMesh: the mutable tetrahedral mesh every FEMorph algorithm edits.
//
// Storage (flat arrays; a tet's vertices and neighbours share one record):
//   points     #V positions
//   tets       #T x 4 vertex ids, positively oriented:
//              (p1 - p0) . ((p2 - p0) x (p3 - p0)) > 0   (VTK_TETRA's order)
//   adjacency  #T x 4 codes; face f of tet t is the face opposite local
//              vertex f. Code >= 0: the neighbour 4 * t' + f' across it.
//              Code < 0: a boundary face, whose region id is -2 - code
//              (-1 = no region).
//   vertex_tet one live incident tet per vertex; the ball of a vertex is found
//              by walking face adjacency from it (vertex neighbourhoods are
//              manifold, build() checks it).
// Dead tets and vertices are tombstoned (first id = -1) and reused from free
// lists; compact() renumbers for output.
//
// Provenance, so the filters can carry attribute data over the edits
// (docs/ARCHITECTURE.md): every tet carries the input cell it descends from;
// every vertex carries a stencil of up to four input vertices and weights
// that interpolate point data onto it.
//
// One file per step, named after it:
//   build_tet_mesh.cpp     build(): checks, orientation, face matching
//   tet_mesh_slots.cpp     slots and free lists, memory_bytes()
//   topology_queries.cpp   vertex ball, neighbours, edge and face queries,
//                          edge rings (walks through face adjacency)
//   classify_vertices.cpp  vertex classes, curve edges
//   move_vertex.cpp        vertex moves with the exact test
//   replace_tets.cpp       cavity replacement behind the local operations
//   sort_spatially.cpp     Morton renumbering
//   compact.cpp            dense copy for output
//   check_consistency.cpp  the invariants, for tests
//   tet_mesh.cpp           to_string(OpStatus), non-inline element access
//   tet_mesh_internal.*    helpers shared by these files
// and the local operations (thesis 2.6.1.3, 2.6.5.3 Fig. 2.45, 2.6.5.4
// Fig. 2.46) in split_edge.cpp, split_face.cpp, collapse_edge.cpp,
// collapse_edge_by_rules.cpp, flip_23.cpp, flip_32.cpp, flip_44.cpp,
// flip_edge_to_fan.cpp, flip_surface_edge.cpp.
//
// Each local operation validates before it commits: no tet with
// non-positive volume (exact predicate), no duplicate edge or face, the link
// condition for collapses. A refused operation leaves the mesh untouched; an
// accepted one lists the live tets it created or changed in touched_tets().
// Operations and queries take an optional `hint`, a tet known to hold the
// edge, which spares a ball walk.
//
// Queries use scratch space inside the mesh: one TetMesh is not safe to use
// from several threads at once, even through const methods.
#pragma once

#include "common/stamps.h"
#include "common/types.h"

#include <cstdint>
#include <vector>

namespace femorph {

namespace internal {
struct FaceSlot;
}

/// Vertex classes of thesis Fig. 2.37: inner, surface (on one boundary
/// region), curve (on a boundary curve between regions: "boundary edge
/// vertex"), corner (where curves meet: "feature vertex").
enum class VertexClass : std::uint8_t { Inner = 0, Surface = 1, Curve = 2, Corner = 3 };

/// Local vertices of face f (opposite local vertex f), ordered so that the
/// face normal (right-hand rule) points out of a positive tet.
constexpr int kTetFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
/// Local vertices of the six edges of a tet.
constexpr int kTetEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

/// Why a local operation was refused.
enum class OpStatus : std::uint8_t {
  Ok = 0,
  InvalidArgument,   // dead vertex/tet, not an edge/face, same vertex twice
  BoundaryEntity,    // the operation needs an interior edge or face
  WrongValence,      // flip 3-2 needs 3 tets around the edge, 4-4 needs 4
  Inverted,          // a resulting tet would have non-positive volume
  DuplicateEntity,   // the new edge or face already exists elsewhere
  LinkCondition,     // collapse would change the topology
  ForbiddenByRule,   // edge classes of thesis Fig. 2.37 (A)-(C)
};
const char* to_string(OpStatus status);

/// Input vertices and weights that interpolate point data onto a vertex.
/// Unused slots have id -1 and weight 0; weights sum to 1.
struct VertexStencil {
  std::array<index_t, 4> ids{{kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex}};
  std::array<double, 4> weights{{0, 0, 0, 0}};
};

/// The two ends of an edge collapse by role: Keep survives, Remove is merged
/// into it. The constructors are explicit, so each call names both roles and
/// swapped arguments do not compile:
///   mesh.collapse_edge(Keep{a}, Remove{b}, &p);
///   mesh.half_edge_collapse(Keep{a}, Remove{b});  // b moves onto a
struct Keep {
  constexpr explicit Keep(index_t vertex) : id(vertex) {}
  index_t id;
};
struct Remove {
  constexpr explicit Remove(index_t vertex) : id(vertex) {}
  index_t id;
};

/// Outcome of plan_collapse_by_rules().
struct CollapsePlan {
  OpStatus status = OpStatus::Ok;
  index_t keep = kInvalidIndex;
  index_t remove = kInvalidIndex;
  Vec3 position = Vec3::Zero();
};

struct BuildOptions {
  /// Accept tets with negative volume that are oriented consistently with
  /// their neighbours (elements inverted by a deformation, for Improve to
  /// repair). Otherwise they are an input error.
  bool allow_inverted = false;
  /// Accept tets with zero volume. Otherwise they are an input error.
  bool allow_degenerate = false;
  /// Region id per tet face (#T x 4, -1 = none), e.g. from FaceRegion.
  /// Empty: all boundary faces get region -1. Ignored on interior faces.
  std::vector<Tet> face_regions;
};

/// What build() found in the input, for messages and for the filters.
struct BuildReport {
  std::size_t flipped_tets = 0;   // all-negative input flipped to positive
  std::size_t inverted_tets = 0;  // negative volume, consistent neighbours
  std::size_t degenerate_tets = 0;
  std::size_t unused_points = 0;  // points no tet refers to (dead, slots reusable)
  std::size_t boundary_faces = 0;
};

/// A compacted copy for output: live vertices and tets renumbered densely.
struct CompactMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  std::vector<Tet> face_regions;             // per tet face, -1 = interior
  std::vector<VertexClass> vertex_classes;
  std::vector<VertexStencil> vertex_origin;  // per output vertex
  std::vector<index_t> tet_origin;           // input tet each output tet descends from
  std::vector<index_t> vertex_map;           // old vertex slot -> new id (-1 dead)
};

class TetMesh {
 public:
  TetMesh() = default;

  /// Builds the mesh from points and tets (0-based). Orientation: an input
  /// whose tets are all negative is flipped consistently; mixed orientation
  /// (neighbouring tets that disagree) is an error naming the count of
  /// offending tets. Also an error: no tets, an index out of range, a vertex
  /// repeated in a tet, a non-finite coordinate, a face shared by more than two
  /// tets, a non-manifold boundary edge or vertex, inverted or degenerate tets
  /// unless allowed by `options`. Points no tet uses are dead from the start
  /// (their slots are reused; compact() drops them).
  /// On failure `*this` is left empty.
  Status build(std::vector<Vec3> points, std::vector<Tet> tets,
               const BuildOptions& options = {}, BuildReport* report = nullptr);

  // ---- sizes and liveness -------------------------------------------------
  index_t vertex_slots() const { return static_cast<index_t>(points_.size()); }
  index_t tet_slots() const { return static_cast<index_t>(rec_.size()); }
  std::size_t live_vertices() const { return points_.size() - free_vertices_.size(); }
  std::size_t live_tets() const { return rec_.size() - free_tets_.size(); }
  bool tet_alive(index_t t) const { return t >= 0 && t < tet_slots() && rec_[t].v[0] >= 0; }
  bool vertex_alive(index_t v) const { return v >= 0 && v < vertex_slots() && vertex_tet_[v] >= 0; }

  // ---- element access -----------------------------------------------------
  const Tet& tet(index_t t) const { return rec_[t].v; }
  const Vec3& point(index_t v) const { return points_[v]; }
  const std::vector<Vec3>& points() const { return points_; }
  /// Neighbour code across face f of tet t (see the header comment).
  index_t adjacency(index_t t, int f) const { return rec_[t].n[f]; }
  bool is_boundary_face(index_t t, int f) const { return rec_[t].n[f] < 0; }
  /// Region of boundary face f of tet t (-1 = none); -1 for interior faces.
  index_t face_region(index_t t, int f) const { return rec_[t].n[f] < 0 ? -2 - rec_[t].n[f] : kInvalidIndex; }
  void set_face_region(index_t t, int f, index_t region);
  /// Local index (0..3) of vertex v in tet t, or -1 (also for t < 0).
  int local_index(index_t t, index_t v) const;
  index_t tet_origin(index_t t) const { return tet_origin_[t]; }
  const VertexStencil& vertex_origin(index_t v) const { return vertex_origin_[v]; }

  // ---- vertex classes and constraints (thesis Fig. 2.37) ------------------
  VertexClass vertex_class(index_t v) const { return vclass_[v]; }
  void set_vertex_class(index_t v, VertexClass c) { vclass_[v] = c; }
  /// Classifies every vertex from the regions of its boundary faces: no
  /// boundary face -> Inner; one region and no curve edge -> Surface; exactly
  /// two curve edges -> Curve; otherwise Corner. A curve edge is a boundary
  /// edge whose two boundary faces have different regions. build() classifies
  /// the same way.
  void classify_vertices();
  /// True when (a, b) is a boundary edge whose two boundary faces lie in
  /// different regions (it lies on a boundary curve).
  bool is_curve_edge(index_t a, index_t b, index_t hint = kInvalidIndex) const;

  // ---- topology queries ---------------------------------------------------
  /// Live tets incident to v, in no particular order (ball of v).
  void vertex_ball(index_t v, std::vector<index_t>& tets) const;
  /// The same walk (same order) with the caller's visit marks: safe from
  /// several threads at once, each with its own marks, while the mesh does
  /// not change. vertex_ball(v, tets) uses the mesh's own marks.
  using WalkMarks = Stamps<std::uint16_t>;
  void vertex_ball(index_t v, std::vector<index_t>& tets, WalkMarks& marks) const;
  /// Vertices adjacent to v by an edge.
  void vertex_neighbors(index_t v, std::vector<index_t>& vertices) const;
  /// A live tet containing edge (a, b), or -1 if the edge does not exist.
  /// `hint`: a tet believed to contain the edge (checked; saves the search
  /// through the ball of a). Every edge query and operation takes one.
  index_t find_edge_tet(index_t a, index_t b, index_t hint = kInvalidIndex) const;
  /// The same with the caller's walk marks (see vertex_ball): safe from
  /// several threads at once.
  index_t find_edge_tet(index_t a, index_t b, index_t hint, WalkMarks& marks) const;
  bool has_edge(index_t a, index_t b) const { return find_edge_tet(a, b) >= 0; }
  /// Tets around edge (a, b) in rotation order. Returns false if the edge does
  /// not exist. *on_boundary tells whether the ring is open (edge on the
  /// boundary); then the first and last tet have the boundary faces.
  bool edge_ring(index_t a, index_t b, std::vector<index_t>& ring, bool* on_boundary,
                 index_t hint = kInvalidIndex) const;
  /// Edge ring with the opposite vertices: ring[i] contains c[i] and c[i+1]
  /// (c has ring.size() + 1 entries when open, ring.size() when closed).
  bool edge_ring_with_vertices(index_t a, index_t b, std::vector<index_t>& ring,
                               std::vector<index_t>& opposite, bool* on_boundary,
                               index_t hint = kInvalidIndex) const;
  /// A live tet having face {a, b, c} and the local face index, or -1.
  index_t find_face(index_t a, index_t b, index_t c, int* local_face = nullptr) const;
  /// True if v lies on a boundary face.
  bool on_boundary(index_t v) const { return vclass_[v] != VertexClass::Inner; }

  // ---- geometry -----------------------------------------------------------
  /// Exact sign of the volume of tet t (+1, 0, -1).
  int orientation(index_t t) const;
  /// Moves v to p if every tet of its ball stays positive (exact test);
  /// otherwise refuses and leaves v in place.
  OpStatus move_vertex(index_t v, const Vec3& p);
  /// The same test with v's ball given by the caller (every live tet that
  /// holds v): no scratch, touched_tets() not updated, so it may run
  /// concurrently for vertices that share no tet (the parallel smoothers).
  OpStatus move_vertex_in_ball(index_t v, const Vec3& p, const std::vector<index_t>& ball);
  /// Moves v without any check (for callers that validated already).
  void set_point(index_t v, const Vec3& p) { points_[v] = p; }

  // ---- local operations (each in its own .cpp) -----------------------------
  /// Edge split (thesis Fig. 2.35 (a)): inserts a vertex on edge (a, b) at
  /// `position` (nullptr: the midpoint), splitting every tet around the edge
  /// in two; boundary faces keep their region. *new_vertex receives its id.
  /// Refused if a new tet would not be positive (possible off the midpoint).
  OpStatus split_edge(index_t a, index_t b, const Vec3* position, index_t* new_vertex,
                      index_t hint = kInvalidIndex);
  /// The same with the edge's ring given as edge_ring_with_vertices() lists
  /// it on the mesh as it is (a caller that evaluated the split has it).
  OpStatus split_edge(index_t a, index_t b, const Vec3* position, index_t* new_vertex,
                      const std::vector<index_t>& ring, const std::vector<index_t>& opposite, bool on_boundary);
  /// Face split (Fig. 2.35 (b)): inserts a vertex on face f of tet t at
  /// `position` (nullptr: the centroid); each tet on the face becomes three.
  OpStatus split_face(index_t t, int f, const Vec3* position, index_t* new_vertex);
  /// Edge collapse (Fig. 2.36 (a)): merges `remove` into `keep` and moves
  /// `keep` to `position` (nullptr: keep's position, i.e. the half-edge
  /// collapse of Fig. 2.39). The tets around the edge vanish. Checks the link
  /// condition and that every remaining tet of both balls stays positive.
  /// Does not apply the rules of Fig. 2.37: see collapse_edge_by_rules().
  OpStatus collapse_edge(Keep keep, Remove remove, const Vec3* position);
  /// The same with both balls given as vertex_ball() lists them on the mesh
  /// as it is (a caller that evaluated the collapse has them: two walks
  /// spared).
  OpStatus collapse_edge(Keep keep, Remove remove, const Vec3* position, const std::vector<index_t>& ball_keep,
                         const std::vector<index_t>& ball_remove);
  /// Per-caller vertex stamps for check_collapse from several threads.
  using VertexStamps = Stamps<std::uint32_t>;
  /// The checks of collapse_edge(keep, remove, &p, ball_keep, ball_remove)
  /// without changing the mesh: Ok when it would collapse. Read only, with
  /// the caller's stamps: safe from several threads at once while the mesh
  /// does not change.
  OpStatus check_collapse(Keep keep, Remove remove, const Vec3& p, const std::vector<index_t>& ball_keep,
                          const std::vector<index_t>& ball_remove, VertexStamps& stamps) const;
  /// collapse_edge(keep, remove, &p, ball_keep, ball_remove) for a caller
  /// whose check_collapse with the same arguments returned Ok on the mesh as
  /// it still is: the checks are not repeated.
  OpStatus collapse_checked_edge(Keep keep, Remove remove, const Vec3& p, const std::vector<index_t>& ball_keep,
                                 const std::vector<index_t>& ball_remove);
  /// Half-edge collapse (Fig. 2.39): `remove` moves onto `keep`.
  OpStatus half_edge_collapse(Keep keep, Remove remove) { return collapse_edge(keep, remove, nullptr); }
  /// Half-edge collapse for the inverted element removal (thesis 2.6.2,
  /// Fig. 2.39) on a mesh built with BuildOptions::allow_inverted: as
  /// half_edge_collapse(), except that a tet of remove's ball that is inverted
  /// (negative volume) before may be non-positive after. Every other tet must
  /// stay positive, so the number of inverted tets drops by those on the edge.
  /// InvalidArgument when the mesh does not allow inverted tets.
  OpStatus half_edge_collapse_keeping_inverted(Keep keep, Remove remove);
  /// The collapse of edge (a, b) that thesis Fig. 2.37 allows: refuses the
  /// forbidden edges (A)-(C) with ForbiddenByRule; otherwise names the vertex
  /// to keep and the position by rules (D)-(G). Improve projects `position`
  /// onto the fitted surface or curve before collapsing.
  CollapsePlan plan_collapse_by_rules(index_t a, index_t b, index_t hint = kInvalidIndex) const;
  /// plan_collapse_by_rules() then collapse_edge(). *kept receives the
  /// surviving vertex (may be null).
  OpStatus collapse_edge_by_rules(index_t a, index_t b, index_t* kept, index_t hint = kInvalidIndex);
  /// Flip 2-3 (Fig. 2.46): the interior face f of tet t and its two tets
  /// become three tets around the edge joining the two opposite vertices.
  OpStatus flip_23(index_t t, int f);
  /// Flip 3-2: the interior edge (a, b) with exactly three tets becomes the
  /// face of the three other vertices, with two tets.
  OpStatus flip_32(index_t a, index_t b, index_t hint = kInvalidIndex);
  /// Flip 4-4: the interior edge (a, b) with exactly four tets (an
  /// octahedron c0 c1 c2 c3 around it) is replaced by the diagonal (c0, c2)
  /// when `diagonal` is 0, (c1, c3) when 1, where c0 is the opposite vertex
  /// order of edge_ring().
  OpStatus flip_44(index_t a, index_t b, int diagonal, index_t hint = kInvalidIndex);
  /// Edge removal into a fan (flip n -> 2n - 4; flips 3-2 and 4-4 are
  /// n = 3 and 4): the interior edge (a, b) goes, and each tet of its ring
  /// that does not hold the ring vertex `apex` becomes two, with b and with
  /// a replaced by apex; the two that hold apex vanish. The mesh a split of
  /// (a, b) followed by the collapse of the new vertex into apex gives,
  /// without making the vertex. ring / opposite as edge_ring_with_vertices()
  /// lists them on the mesh as it is. Refused if a new tet would not be
  /// positive or, with check_edges, if an edge (apex, c) it makes (with
  /// three ring tets: the face of the ring's vertices) exists already (a
  /// caller that checked this on the mesh as it is may skip it).
  OpStatus flip_edge_to_fan(index_t a, index_t b, index_t apex, const std::vector<index_t>& ring,
                            const std::vector<index_t>& opposite, bool check_edges = true);
  /// Surface edge flip (Fig. 2.45): the boundary edge (a, b), whose two
  /// boundary faces (a, b, c) and (b, a, d) lie in one region, becomes
  /// (c, d) by an edge split at the midpoint followed by the half-edge
  /// collapse of the new vertex onto c. Refused when either step would be.
  OpStatus flip_surface_edge(index_t a, index_t b, index_t hint = kInvalidIndex);

  /// Replaces the live tets `old_tets` (a cavity, e.g. a region adapted as a
  /// mesh of its own) by `new_tets`. A vertex id v >= 0 of a new tet is an
  /// existing vertex; v < 0 is new point -1 - v of `new_points` (created with
  /// `new_point_origins`, class Inner). The boundary of the new tets must be
  /// the cavity's boundary, face for face; otherwise nothing changes and the
  /// call fails. Vertices of the cavity no new tet uses are deleted. Fills
  /// touched_ with the new tets; `created`, when given, receives the ids of
  /// the new points. `new_boundary`, when given, lists the boundary faces of
  /// the new tets (ids as in new_tets, any order), known to the caller (a
  /// mesh's faces without neighbour): the check then sorts those only.
  Status replace_cavity(const std::vector<index_t>& old_tets, const std::vector<Tet>& new_tets,
                        const std::vector<index_t>& new_origins, const std::vector<Vec3>& new_points,
                        const std::vector<VertexStencil>& new_point_origins, std::vector<index_t>* created = nullptr,
                        const std::vector<std::array<index_t, 3>>* new_boundary = nullptr);

  /// replace_cavity for a cavity on the domain's boundary (Adapt's assembly
  /// mode, thesis 3.7.4): the cavity's faces with kept tets must be faces of
  /// the new tets' boundary; its faces on the domain's boundary may change
  /// (the new tets' other boundary faces are the domain's boundary there).
  /// Vertices of the cavity no new tet uses are deleted; the new tets'
  /// vertices are classified again (a boundary vertex may become inner).
  Status replace_boundary_cavity(const std::vector<index_t>& old_tets, const std::vector<Tet>& new_tets,
                                 const std::vector<index_t>& new_origins, const std::vector<Vec3>& new_points,
                                 const std::vector<VertexStencil>& new_point_origins,
                                 std::vector<index_t>* created = nullptr);

  /// Live tets the last accepted operation created or changed.
  const std::vector<index_t>& touched_tets() const { return touched_; }

  // ---- output and checks ---------------------------------------------------
  /// Dense copy of the live mesh with provenance and face regions.
  CompactMesh compact() const;
  /// Renumbers the live vertices along a Morton curve through their
  /// positions and the live tets by their lowest new vertex id, dropping
  /// dead slots: neighbours then sit close in memory, which edits scatter
  /// (new tets fill freed slots anywhere). Every id held outside the mesh
  /// becomes stale. Returns the old-to-new vertex map (-1: dead).
  std::vector<index_t> sort_spatially();
  /// Bytes held by the mesh's arrays (capacity, scratch space included).
  std::size_t memory_bytes() const;
  /// Checks the internal invariants (adjacency symmetric and matching the
  /// faces, vertex_tet incident and alive, free lists, orientation positive
  /// unless inverted tets were allowed). For tests; O(#T).
  Status check_consistency() const;

 private:
  friend struct TetMeshAccess;  // tests and benchmarks

  index_t new_tet(const Tet& vertices, index_t origin);
  void delete_tet(index_t t);
  index_t new_vertex(const Vec3& p, const VertexStencil& origin, VertexClass c);
  void delete_vertex(index_t v);
  /// Replaces the live tets `old_tets` (a cavity) by `new_tets`, whose
  /// boundary is the cavity's boundary once vertex `rename_from` is renamed
  /// `rename_to` (-1: no renaming). Rebuilds face adjacency inside the new
  /// tets and with the outside, zips the two outer faces of a vanished tet
  /// (collapse), keeps boundary regions and vertex_tet. Fills touched_.
  /// The caller has validated the result.
  void replace_tets(const std::vector<index_t>& old_tets, const std::vector<Tet>& new_tets,
                    const std::vector<index_t>& new_origins, index_t rename_from, index_t rename_to);
  /// Links two faces of a cavity with the same vertices (see replace_tets).
  void link_faces(const internal::FaceSlot& p, const internal::FaceSlot& q);
  /// Whether an open ring (from edge_ring_with_vertices) lies on a curve:
  /// its two boundary faces have different regions.
  bool open_ring_on_curve(const std::vector<index_t>& ring, const std::vector<index_t>& opposite) const;
  /// collapse_edge() with either ball given (non-null) or walked.
  OpStatus collapse_edge_with(Keep keep, Remove remove, const Vec3* position,
                              const std::vector<index_t>* given_keep, const std::vector<index_t>* given_remove);
  /// The tets of ball_remove on the edge into `ring`; false when
  /// (keep, remove) is no edge.
  bool collapse_cavity(Keep keep, const std::vector<index_t>& ball_remove, std::vector<index_t>& ring);
  /// The change of a collapse whose checks passed; `ring`: the tets on the
  /// edge (collapse_cavity), `unchanged`: the tets of ball_keep off it.
  void commit_collapse(Keep keep, Remove remove, const Vec3& p, const std::vector<index_t>& ball_remove,
                       const std::vector<index_t>& ring, const std::vector<index_t>& unchanged);
  /// Link condition of thesis 2.6.1.3 / Dey et al. for collapsing (a, b):
  /// Lk(a) n Lk(b) = Lk(ab), with a vertex at infinity coning the boundary.
  /// ball_a, ball_b: the balls of a and b; ring: the tets on the edge;
  /// `mark`: one stamp per vertex slot; in_a, in_ring: two values no slot holds.
  bool link_condition(index_t a, index_t b, const std::vector<index_t>& ball_a, const std::vector<index_t>& ball_b,
                      const std::vector<index_t>& ring, std::uint32_t* mark, std::uint32_t in_a,
                      std::uint32_t in_ring) const;
  /// The class of vertex v from its ball (every live tet holding v).
  VertexClass classify_ball(index_t v, const std::vector<index_t>& ball) const;
  /// A fresh mark for tet_marks_, grown to the tet slots.
  std::uint16_t next_tet_mark() const { return tet_marks_.next(rec_.size()); }
  /// The ball of v breadth-first from vertex_tet_[v] into `out`. With
  /// `stop_at` >= 0 the walk ends at the first tet holding that vertex too
  /// and returns it (else -1): the edge search need not walk the rest.
  index_t walk_ball(index_t v, std::vector<index_t>& out, std::uint16_t* marks, std::uint16_t mark,
                    index_t stop_at = kInvalidIndex) const;
  /// find_edge_tet's checks that need no walk: true when they decide (*t a
  /// tet on the edge, or -1 for dead or equal ends).
  bool edge_tet_without_walk(index_t a, index_t b, index_t hint, index_t* t) const;

  /// A tet's vertices and neighbour codes side by side: one cache line
  /// holds two tets, and local operations read both.
  struct alignas(32) TetRecord {
    Tet v;
    Tet n;
  };

  std::vector<Vec3> points_;
  std::vector<TetRecord> rec_;
  std::vector<index_t> vertex_tet_;
  std::vector<VertexClass> vclass_;
  std::vector<index_t> tet_origin_;
  std::vector<VertexStencil> vertex_origin_;
  std::vector<index_t> free_tets_;
  std::vector<index_t> free_vertices_;
  bool allow_inverted_ = false;
  bool keep_inverted_ = false;  // set by half_edge_collapse_keeping_inverted

  // Scratch space reused by queries and operations (no allocation per op).
  mutable WalkMarks tet_marks_;  // walks and replace_tets
  VertexStamps link_stamps_;     // check_collapse from collapse_edge
  mutable std::vector<index_t> scratch_ring_, scratch_verts_, scratch_ball_, scratch_ball2_;
  std::vector<Tet> scratch_new_;
  std::vector<index_t> scratch_origin_;
  std::vector<index_t> touched_;
};

/// The live tets' vertex ids in slot order (a fresh mesh: the input's tets,
/// orientation as built).
std::vector<Tet> live_tet_list(const TetMesh& mesh);

}  // namespace femorph
