// The contact part of a motion step (thesis 3.5.1: "if M_m contacts with
// other object meshes, all steps are performed"): contact detection at the
// new pose (3.4.2), the zone of tets removed around the contact (3.5.2,
// here the objects' tets touching it too), the two contact patches merged
// into one surface (3.5.4, merge_contact_surfaces) and the zone refilled by
// TetGen with no Steiner point on its boundary nor on the new surfaces
// (3.5.5). The zone is part of the adapted region, so it is spliced back
// with it.
#include "adapt/contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace femorph {


namespace {

int material_of(const TetMesh& mesh, const std::vector<int>& material_by_origin, index_t t) {
  return material_by_origin[mesh.tet_origin(t)];
}

}  // namespace

Status AdaptSession::init_contact() {
  contact_.reset();
  const std::vector<ObjectBoundary> objects = object_boundaries(mesh_, material_);
  if (objects.size() < 2) return Status::success();
  auto state = std::make_shared<AdaptContactState>();
  double edge = 0;
  std::size_t counted = 0;
  for (const ObjectBoundary& b : objects) {
    ObjectSurfaceInfo info;
    const Status s = segment_object(mesh_.points(), b, info);
    if (!s) return Status::failure("contact detection needs each object's surface segmented: " + s.message);
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Tri& f : b.faces)
      for (const index_t v : f) {
        lo = lo.cwiseMin(mesh_.point(v));
        hi = hi.cwiseMax(mesh_.point(v));
      }
    edge += info.mean_edge * static_cast<double>(b.faces.size());
    counted += b.faces.size();
    if (b.material == options_.moving_object) {
      state->moving = info;
      state->moving_lo = lo;
      state->moving_hi = hi;
    } else {
      state->others.push_back(info);
      state->other_lo.push_back(lo);
      state->other_hi.push_back(hi);
    }
  }
  state->spacing = edge / static_cast<double>(std::max<std::size_t>(counted, 1));
  state->tolerance = 1e-4 * state->spacing;
  contact_ = state;
  return Status::success();
}

std::vector<ContactRegion> AdaptSession::contacts_at(const RigidPose& to) const {
  std::vector<ContactRegion> out;
  if (!contact_) return out;
  AdaptContactState& st = *contact_;
  if (st.cached_version == mesh_version_ && st.cached_pose.R == to.R && st.cached_pose.t == to.t) return st.cached;
  out = find_contacts(to);
  st.cached_pose = to;
  st.cached_version = mesh_version_;
  st.cached = out;
  return out;
}

std::vector<ContactRegion> AdaptSession::find_contacts(const RigidPose& to) const {
  std::vector<ContactRegion> out;
  const AdaptContactState& st = *contact_;
  // The moving object's box at the new pose (its corners), with a margin.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int c = 0; c < 8; ++c) {
    const Vec3 x((c & 1) ? st.moving_hi.x() : st.moving_lo.x(), (c & 2) ? st.moving_hi.y() : st.moving_lo.y(),
                 (c & 4) ? st.moving_hi.z() : st.moving_lo.z());
    lo = lo.cwiseMin(to.apply(x));
    hi = hi.cwiseMax(to.apply(x));
  }
  const double margin = st.spacing;
  std::vector<std::size_t> near;
  for (std::size_t k = 0; k < st.others.size(); ++k)
    if ((lo.array() - margin <= st.other_hi[k].array()).all() && (st.other_lo[k].array() <= hi.array() + margin).all())
      near.push_back(k);
  if (near.empty() && st.shared.empty()) return out;
  const std::vector<ObjectBoundary> objects = object_boundaries(mesh_, material_);
  const ObjectBoundary* moving = nullptr;
  for (const ObjectBoundary& b : objects)
    if (b.material == options_.moving_object) moving = &b;
  if (!moving) return out;
  // The moving object's vertices at the new pose: rest positions for its
  // own, the current position moved relatively for shared ones.
  const RigidPose relative = to.after(pose_.inverse());
  const auto moved = [&](index_t v) {
    const index_t k = v < static_cast<index_t>(object_index_.size()) ? object_index_[v] : kInvalidIndex;
    return k >= 0 ? to.apply(object_rest_[k]) : relative.apply(mesh_.point(v));
  };
  std::vector<SurfacePrimitive> posed;
  for (const SurfacePrimitive& s : st.moving.regions) posed.push_back(transform_surface(s, to));
  const std::vector<index_t> moving_region = classify_object_faces(moved, moving->faces, posed, st.tolerance);
  for (const std::size_t k : near) {
    const ObjectSurfaceInfo& info = st.others[k];
    for (const ObjectBoundary& b : objects) {
      if (b.material != info.material) continue;
      const auto fixed = [&](index_t v) { return mesh_.point(v); };
      const std::vector<index_t> region = classify_object_faces(fixed, b.faces, info.regions, st.tolerance);
      // Objects about to touch (within one spacing) count: their zone is
      // removed before the gap closes (3.5.2).
      std::vector<ContactRegion> c = detect_contacts(moved, *moving, moving_region, posed, mesh_.points(), b, region,
                                                     info.regions, st.tolerance, std::max(info.scale, st.moving.scale),
                                                     st.spacing);
      for (ContactRegion& r : c) out.push_back(std::move(r));
    }
  }
  return out;
}

std::vector<index_t> AdaptSession::contact_zone(const std::vector<ContactRegion>& contacts) const {
  std::unordered_set<index_t> seeds;
  for (const ContactRegion& c : contacts) {
    seeds.insert(c.moving_vertices.begin(), c.moving_vertices.end());
    seeds.insert(c.other_vertices.begin(), c.other_vertices.end());
  }
  if (contact_) seeds.insert(contact_->shared.begin(), contact_->shared.end());
  std::set<int> allowed{0, options_.moving_object};
  for (const ContactRegion& c : contacts) allowed.insert(c.other_material);
  if (contact_)
    for (const index_t v : contact_->shared) {
      std::vector<index_t> ball;
      mesh_.vertex_ball(v, ball);
      for (const index_t t : ball) allowed.insert(material_of(mesh_, material_, t));
    }
  // The tets around the seeds, then one ring more (a margin around the
  // contact for the merged patches' boundaries).
  std::unordered_set<index_t> zone;
  std::vector<index_t> ball;
  for (const index_t v : seeds) {
    mesh_.vertex_ball(v, ball);
    for (const index_t t : ball)
      if (allowed.count(material_of(mesh_, material_, t))) zone.insert(t);
  }
  std::unordered_set<index_t> ring;
  for (const index_t t : zone)
    for (const index_t v : mesh_.tet(t)) ring.insert(v);
  for (const index_t v : ring) {
    mesh_.vertex_ball(v, ball);
    for (const index_t t : ball)
      if (allowed.count(material_of(mesh_, material_, t))) zone.insert(t);
  }
  // A hole TetGen can fill has a manifold boundary: where the zone meets
  // itself along an edge only (two fans of boundary faces), it takes every
  // tet around that edge.
  for (int pass = 0; pass < 20; ++pass) {
    std::map<std::pair<index_t, index_t>, int> faces_on_edge;
    for (const index_t t : zone)
      for (int f = 0; f < 4; ++f) {
        const index_t code = mesh_.adjacency(t, f);
        if (code >= 0 && zone.count(code >> 2)) continue;
        const Tet& T = mesh_.tet(t);
        for (int i = 0; i < 3; ++i) {
          const index_t a = T[kTetFace[f][i]], b = T[kTetFace[f][(i + 1) % 3]];
          ++faces_on_edge[{std::min(a, b), std::max(a, b)}];
        }
      }
    bool grown = false;
    for (const auto& [e, n] : faces_on_edge) {
      if (n <= 2) continue;
      mesh_.vertex_ball(e.first, ball);
      for (const index_t t : ball) {
        const Tet& T = mesh_.tet(t);
        if (std::find(T.begin(), T.end(), e.second) == T.end()) continue;
        if (!allowed.count(material_of(mesh_, material_, t))) continue;
        grown |= zone.insert(t).second;
      }
    }
    if (!grown) break;
  }
  std::vector<index_t> out(zone.begin(), zone.end());
  std::sort(out.begin(), out.end());
  close_region(mesh_, out, [&](index_t t) { return allowed.count(material_of(mesh_, material_, t)) > 0; });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<index_t> AdaptSession::fixed_object_ring(const std::vector<index_t>& zone, bool moving) const {
  std::unordered_set<index_t> in_zone(zone.begin(), zone.end()), vertices;
  for (const index_t t : zone)
    for (const index_t v : mesh_.tet(t)) vertices.insert(v);
  std::vector<index_t> ring, ball;
  for (const index_t v : vertices) {
    mesh_.vertex_ball(v, ball);
    for (const index_t t : ball) {
      const int m = material_of(mesh_, material_, t);
      if (m > 0 && (moving || m != options_.moving_object) && !in_zone.count(t)) ring.push_back(t);
    }
  }
  std::sort(ring.begin(), ring.end());
  ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  return ring;
}

Status AdaptSession::remesh_contact_zone(RegionMesh& rm, const std::vector<index_t>& zone,
                                         const std::vector<ContactRegion>& contacts, const RigidPose& to) {
  TetMesh& sub = rm.mesh;
  const index_t slots = sub.vertex_slots();
  const auto rm_material = [&](index_t t) {
    return material_of(mesh_, material_, rm.global_tet[sub.tet_origin(t)]);
  };
  const int moving = options_.moving_object;
  // Vertices of the zone on the moving object and on another object.
  std::vector<std::uint8_t> on_moving(static_cast<std::size_t>(slots), 0), on_other(static_cast<std::size_t>(slots), 0);
  for (index_t t = 0; t < sub.tet_slots(); ++t) {
    if (!sub.tet_alive(t)) continue;
    const int m = rm_material(t);
    for (const index_t v : sub.tet(t)) {
      if (m == moving) on_moving[v] = 1;
      else if (m > 0) on_other[v] = 1;
    }
  }
  // PLC points: the region's, then the moving object's copies of shared
  // vertices (at the new pose), then the merges' crossings.
  std::vector<Vec3> points(sub.points().begin(), sub.points().end());
  const RigidPose relative = to.after(pose_.inverse());
  std::unordered_map<index_t, index_t> copy;
  const auto moving_id = [&](index_t v) {
    if (!(on_moving[v] && on_other[v])) return v;
    const auto it = copy.find(v);
    if (it != copy.end()) return it->second;
    const index_t id = static_cast<index_t>(points.size());
    points.push_back(relative.apply(sub.point(v)));
    copy.emplace(v, id);
    return id;
  };
  std::vector<HoleFacet> facets = hole_facets(sub, zone, rm_material);
  // 3.7.4, an assembly: a facet on the domain's boundary (no tet beyond it
  // in the whole mesh) is a part's surface, a contact patch's face where it
  // lies on the contact surface; it may change (replace_boundary_cavity).
  const auto on_domain_boundary = [&](const HoleFacet& f) {
    if (!assembly_ || (f.front >= 0 && f.back >= 0)) return false;
    for (const index_t v : f.v)
      if (v >= static_cast<index_t>(rm.global_vertex.size())) return false;
    int lf = 0;
    const index_t t = mesh_.find_face(rm.global_vertex[f.v[0]], rm.global_vertex[f.v[1]], rm.global_vertex[f.v[2]], &lf);
    return t >= 0 && mesh_.adjacency(t, lf) < 0;
  };
  // Faces of each contact's two patches leave the facets for the merge.
  std::vector<HoleFacet> kept;
  std::vector<std::uint8_t> kept_outside;  // per kept facet: on the domain's boundary
  std::vector<std::vector<Tri>> moving_patch(contacts.size()), other_patch(contacts.size());
  // The same faces as facets (the moving ones with the copies' ids), for
  // when a contact has nothing to merge.
  std::vector<std::vector<HoleFacet>> moving_source(contacts.size()), other_source(contacts.size());
  std::vector<std::vector<std::uint8_t>> moving_outside(contacts.size()), other_outside(contacts.size());
  const auto keep = [&](const HoleFacet& f, bool outside) {
    kept.push_back(f);
    kept_outside.push_back(outside);
  };
  const double tol = contact_->tolerance;
  const double cos30 = std::cos(kPi / 6);
  const auto on_surface = [&](const SurfacePrimitive& s, const Tri& f) {
    const Vec3 a = points[f[0]], b = points[f[1]], c = points[f[2]];
    if (distance(s, a) > tol || distance(s, b) > tol || distance(s, c) > tol) return false;
    const Vec3 n = (b - a).cross(c - a);
    return n.norm() > 0 && std::abs(n.normalized().dot(surface_normal(s, (a + b + c) / 3))) >= cos30;
  };
  for (HoleFacet f : facets) {
    const bool outside = on_domain_boundary(f);
    if ((f.front < 0 || f.back < 0) && !outside) {
      keep(f, false);
      continue;
    }
    // An interface: the moving object's side uses its copies.
    bool taken = false;
    for (std::size_t k = 0; k < contacts.size() && !taken; ++k) {
      const ContactRegion& c = contacts[k];
      const bool m_side = f.front == moving || f.back == moving;
      const bool c_side = f.front == c.other_material || f.back == c.other_material;
      if (m_side) {
        Tri t = f.v;
        for (index_t& v : t) v = moving_id(v);
        if (f.back != moving) std::swap(t[1], t[2]);  // outward from the moving object
        if (on_surface(c.surface, t)) {
          moving_patch[k].push_back(t);
          HoleFacet h = f;
          for (index_t& v : h.v) v = moving_id(v);
          moving_source[k].push_back(h);
          moving_outside[k].push_back(outside);
          taken = true;
        }
      }
      if (c_side) {
        Tri t = f.v;
        if (f.back != c.other_material) std::swap(t[1], t[2]);
        if (on_surface(c.surface, t)) {
          other_patch[k].push_back(t);
          other_source[k].push_back(f);
          other_outside[k].push_back(outside);
          taken = true;
        }
      }
    }
    if (taken) continue;
    if (f.front == moving || f.back == moving)
      for (index_t& v : f.v) v = moving_id(v);
    keep(f, outside);
  }
  // Only the moving patch's faces near the other patch (within two
  // spacings in the chart) are merged; the rest stay as they are (a patch
  // must not wrap around its surface).
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (other_patch[k].empty()) continue;
    Vec3 centre = Vec3::Zero();
    for (const Tri& f : other_patch[k]) centre += (points[f[0]] + points[f[1]] + points[f[2]]) / 3;
    centre /= static_cast<double>(other_patch[k].size());
    const SurfaceChart chart = make_surface_chart(contacts[k].surface, closest_point(contacts[k].surface, centre));
    ChartTriangles near(chart, contact_->spacing);
    for (const Tri& f : other_patch[k]) near.add(points[f[0]], points[f[1]], points[f[2]]);
    std::vector<Tri> trimmed;
    std::vector<HoleFacet> trimmed_source;
    std::vector<std::uint8_t> trimmed_outside;
    for (std::size_t i = 0; i < moving_patch[k].size(); ++i) {
      const Tri& f = moving_patch[k][i];
      if (near.contains(chart.map((points[f[0]] + points[f[1]] + points[f[2]]) / 3), 2 * contact_->spacing)) {
        trimmed.push_back(f);
        trimmed_source.push_back(moving_source[k][i]);
        trimmed_outside.push_back(moving_outside[k][i]);
      } else {
        keep(moving_source[k][i], moving_outside[k][i]);
      }
    }
    moving_patch[k] = std::move(trimmed);
    moving_source[k] = std::move(trimmed_source);
    moving_outside[k] = std::move(trimmed_outside);
  }
  // A contact with one patch empty has nothing to merge: its faces stay.
  for (std::size_t k = 0; k < contacts.size(); ++k)
    if (moving_patch[k].empty() || other_patch[k].empty()) {
      for (std::size_t i = 0; i < moving_source[k].size(); ++i) keep(moving_source[k][i], moving_outside[k][i]);
      for (std::size_t i = 0; i < other_source[k].size(); ++i) keep(other_source[k][i], other_outside[k][i]);
      moving_patch[k].clear();
      other_patch[k].clear();
    }
  // The other object's vertices may slide in the merge where no kept tet
  // holds them (off the zone's boundary).
  std::vector<std::uint8_t> on_hole_boundary(points.size(), 0);
  for (const HoleFacet& f : facets)
    if (f.front < 0 || f.back < 0)
      for (const index_t v : f.v) on_hole_boundary[v] = 1;
  const auto movable = [&](index_t v) {
    return v < static_cast<index_t>(on_hole_boundary.size()) && !on_hole_boundary[v];
  };
  std::vector<HoleFacet> merged_faces;
  std::map<std::pair<index_t, index_t>, std::vector<index_t>> split;
  std::map<index_t, index_t> replaced;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (moving_patch[k].empty() || other_patch[k].empty()) continue;
    MergedContact merged;
    const auto at = [&points](index_t v) { return points[v]; };
    const Status s = merge_contact_surfaces(contacts[k].surface, moving_patch[k], other_patch[k], at, moving,
                                            contacts[k].other_material, assembly_ ? -1 : 0,
                                            static_cast<index_t>(points.size()),
                                            0.3 * contact_->spacing, merged, movable);
    if (!s) return s;
    points.insert(points.end(), merged.new_points.begin(), merged.new_points.end());
    merged_faces.insert(merged_faces.end(), merged.faces.begin(), merged.faces.end());
    split.insert(merged.split_edges.begin(), merged.split_edges.end());
    replaced.insert(merged.replaced.begin(), merged.replaced.end());
  }
  // The other facets follow the merge: replaced vertices, and a fan where a
  // patch boundary edge they share received points.
  std::vector<HoleFacet> all;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    HoleFacet f = kept[i];
    for (index_t& v : f.v) {
      const auto it = replaced.find(v);
      if (it != replaced.end()) v = it->second;
    }
    int e = -1;
    const std::vector<index_t>* between = nullptr;
    for (int i = 0; i < 3 && e < 0; ++i) {
      const index_t a = f.v[i], b = f.v[(i + 1) % 3];
      const auto it = split.find({std::min(a, b), std::max(a, b)});
      if (it != split.end()) {
        e = i;
        between = &it->second;
      }
    }
    if (e < 0) {
      all.push_back(f);
      continue;
    }
    if ((f.front < 0 || f.back < 0) && !kept_outside[i])
      return Status::failure("the contact reaches the edge of the removed zone (a larger zone is needed)");
    // Fan from the opposite corner over the edge's points, in order a -> b.
    const index_t a = f.v[e], b = f.v[(e + 1) % 3], o = f.v[(e + 2) % 3];
    std::vector<index_t> chain{a};
    if (a < b) chain.insert(chain.end(), between->begin(), between->end());
    else chain.insert(chain.end(), between->rbegin(), between->rend());
    chain.push_back(b);
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) all.push_back({{{chain[i], chain[i + 1], o}}, f.front, f.back});
  }
  all.insert(all.end(), merged_faces.begin(), merged_faces.end());
  std::vector<Tet> tets;
  std::vector<int> material;
  Status s = tetrahedralize_hole(points, all, 1.4, tets, material);
  if (!s) return Status::failure("the contact zone could not be refilled: " + s.message);
  // Into the region mesh: existing slots keep their ids, the rest are new.
  std::unordered_map<int, index_t> origin_of;  // material -> a zone tet's build-time id
  for (const index_t t : zone) origin_of.emplace(rm_material(t), sub.tet_origin(t));
  std::vector<Tet> new_tets;
  std::vector<index_t> origins;
  for (std::size_t i = 0; i < tets.size(); ++i) {
    Tet T = tets[i];
    for (index_t& v : T) v = v < slots ? v : -1 - (v - slots);
    new_tets.push_back(T);
    const auto it = origin_of.find(material[i]);
    if (it == origin_of.end()) return Status::failure("the contact zone's refill has a material the zone had not");
    origins.push_back(it->second);
  }
  const std::vector<Vec3> new_points(points.begin() + slots, points.end());
  const std::vector<VertexStencil> new_origins(new_points.size());
  s = assembly_ ? sub.replace_boundary_cavity(zone, new_tets, origins, new_points, new_origins)
                : sub.replace_cavity(zone, new_tets, origins, new_points, new_origins);
  if (!s) return Status::failure("the contact zone's refill does not fit its hole: " + s.message);
  return Status::success();
}

Status AdaptSession::check_assembly_overlap(const RigidPose& target) const {
  std::vector<Vec3> moved;
  moved.reserve(object_surface_.size());
  for (const index_t v : object_surface_) moved.push_back(target.apply(object_rest_[object_index_[v]]));
  return detect_overlap(mesh_, material_, options_.moving_object, moved, kOverlapTolerance * contact_->spacing);
}

Status AdaptSession::check_shared_vertices(const RigidPose& target) const {
  const RigidPose relative = target.after(pose_.inverse());
  const std::vector<ContactRegion> contacts = contacts_at(pose_);
  // Each shared vertex's other object: its outward normal there (the sum of
  // its boundary faces' at the vertex), to tell its side of the surface.
  std::vector<index_t> ball;
  for (const index_t v : contact_->shared) {
    const Vec3 p = mesh_.point(v), moved = relative.apply(p);
    mesh_.vertex_ball(v, ball);
    for (const ContactRegion& c : contacts) {
      if (distance(c.surface, p) > contact_->tolerance) continue;
      Vec3 outward = Vec3::Zero();
      for (const index_t t : ball) {
        if (material_of(mesh_, material_, t) != c.other_material) continue;
        const int lv = mesh_.local_index(t, v);
        for (int f = 0; f < 4; ++f) {
          if (f == lv) continue;
          const index_t code = mesh_.adjacency(t, f);
          if (code >= 0 && material_of(mesh_, material_, code >> 2) == c.other_material) continue;
          const Tet& T = mesh_.tet(t);
          const Vec3 a = mesh_.point(T[kTetFace[f][0]]), b = mesh_.point(T[kTetFace[f][1]]),
                     d = mesh_.point(T[kTetFace[f][2]]);
          outward += (b - a).cross(d - a);
        }
      }
      if (outward.squaredNorm() == 0) continue;
      // Into the other object: beyond its surface on its side (sliding and
      // turning on the surface keep the shared vertices on it).
      const double side = outward.dot(surface_normal(c.surface, p)) > 0 ? -1 : 1;
      const double depth = side * signed_distance(c.surface, moved);
      if (depth > contact_->tolerance + 0.05 * contact_->spacing) {
        std::ostringstream os;
        os << "the moving object (material " << options_.moving_object << ") would penetrate object "
           << c.other_material << " by " << depth << " at (" << moved.x() << ", " << moved.y() << ", " << moved.z()
           << ")";
        return Status::failure(os.str());
      }
      break;
    }
  }
  return Status::success();
}

void AdaptSession::rebuild_object_vertices(const std::vector<index_t>& placed, const RigidPose& to) {
  // The moving object's vertices after a contact step (before it moves to
  // the new pose): those only its tets use (a vertex shared with another
  // object stays with that one), with their rest positions kept or, for the
  // vertices `placed` (the adapted region's, at the new pose `to` already:
  // moved, refilled or improved), mapped back from it.
  const RigidPose back = to.inverse();
  std::unordered_set<index_t> is_new(placed.begin(), placed.end());
  std::vector<std::uint8_t> mine(static_cast<std::size_t>(mesh_.vertex_slots()), 0),
      other(static_cast<std::size_t>(mesh_.vertex_slots()), 0), surface(static_cast<std::size_t>(mesh_.vertex_slots()), 0);
  for (index_t t = 0; t < mesh_.tet_slots(); ++t) {
    if (!mesh_.tet_alive(t)) continue;
    const int m = material_of(mesh_, material_, t);
    for (const index_t v : mesh_.tet(t)) {
      if (m == options_.moving_object) mine[v] = 1;
      else if (m > 0) other[v] = 1;
    }
    if (m != options_.moving_object) continue;
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh_.adjacency(t, f);
      if (code >= 0 && material_of(mesh_, material_, code >> 2) == options_.moving_object) continue;
      for (int k = 0; k < 3; ++k) surface[mesh_.tet(t)[kTetFace[f][k]]] = 1;
    }
  }
  std::vector<index_t> index(static_cast<std::size_t>(mesh_.vertex_slots()), kInvalidIndex);
  std::vector<index_t> vertices, surface_vertices;
  std::vector<Vec3> rest;
  if (contact_) contact_->shared.clear();
  for (index_t v = 0; v < mesh_.vertex_slots(); ++v) {
    if (!mesh_.vertex_alive(v) || !mine[v]) continue;
    if (other[v]) {
      if (contact_) contact_->shared.push_back(v);
      continue;
    }
    const index_t old =
        !is_new.count(v) && v < static_cast<index_t>(object_index_.size()) ? object_index_[v] : kInvalidIndex;
    index[v] = static_cast<index_t>(vertices.size());
    vertices.push_back(v);
    rest.push_back(old >= 0 ? object_rest_[old] : back.apply(mesh_.point(v)));
    if (surface[v]) surface_vertices.push_back(v);
  }
  object_index_ = std::move(index);
  object_vertices_ = std::move(vertices);
  object_rest_ = std::move(rest);
  object_surface_ = std::move(surface_vertices);
}

Status improve_material_parts(RegionMesh& rm, const std::vector<int>& material_by_origin, const TetMesh& mesh,
                              const DensityGrid* density, double density_scale, double quality_floor) {
  std::set<int> materials;
  for (index_t t = 0; t < rm.mesh.tet_slots(); ++t)
    if (rm.mesh.tet_alive(t)) materials.insert(material_of(mesh, material_by_origin, rm.global_tet[rm.mesh.tet_origin(t)]));
  for (const int m : materials) {
    const Status s = improve_material_part(rm, m, material_by_origin, mesh, density, density_scale, quality_floor);
    if (!s) return s;
  }
  return Status::success();
}

Status improve_material_part(RegionMesh& rm, int material, const std::vector<int>& material_by_origin,
                             const TetMesh& mesh, const DensityGrid* density, double density_scale,
                             double quality_floor) {
  TetMesh& sub = rm.mesh;
  std::vector<index_t> space;
  for (index_t t = 0; t < sub.tet_slots(); ++t)
    if (sub.tet_alive(t) && material_of(mesh, material_by_origin, rm.global_tet[sub.tet_origin(t)]) == material)
      space.push_back(t);
  open_region(sub, space);
  if (space.empty()) return Status::success();
  RegionMesh part;
  Status s = make_region_mesh(sub, space, part);
  if (!s) return s;
  s = improve_deformed_region(part, density, density_scale, quality_floor);
  if (!s) return s;
  const index_t built = static_cast<index_t>(part.global_vertex.size());
  const TetMesh& p = part.mesh;
  std::vector<index_t> name(static_cast<std::size_t>(p.vertex_slots()), kInvalidIndex);
  std::vector<Vec3> new_points;
  std::vector<VertexStencil> new_origins;
  for (index_t v = 0; v < p.vertex_slots(); ++v) {
    if (!p.vertex_alive(v)) continue;
    if (v < built) {
      name[v] = part.global_vertex[v];
      continue;
    }
    name[v] = -1 - static_cast<index_t>(new_points.size());
    new_points.push_back(p.point(v));
    VertexStencil o = p.vertex_origin(v);
    for (index_t& id : o.ids)
      if (id >= 0) id = id < built ? part.global_vertex[id] : kInvalidIndex;
    new_origins.push_back(o);
  }
  std::vector<Tet> tets;
  std::vector<index_t> origins;
  for (index_t t = 0; t < p.tet_slots(); ++t) {
    if (!p.tet_alive(t)) continue;
    Tet T = p.tet(t);
    for (index_t& v : T) v = name[v];
    tets.push_back(T);
    origins.push_back(sub.tet_origin(part.global_tet[p.tet_origin(t)]));
  }
  std::vector<Vec3> previous(static_cast<std::size_t>(built));
  for (index_t v = 0; v < built; ++v) {
    previous[v] = sub.point(part.global_vertex[v]);
    if (p.vertex_alive(v)) sub.set_point(part.global_vertex[v], p.point(v));
  }
  s = sub.replace_cavity(space, tets, origins, new_points, new_origins);
  if (!s) {
    for (index_t v = 0; v < built; ++v) sub.set_point(part.global_vertex[v], previous[v]);
    return Status::failure("the improved part could not be put back (" + s.message + ")");
  }
  return Status::success();
}

}  // namespace femorph
