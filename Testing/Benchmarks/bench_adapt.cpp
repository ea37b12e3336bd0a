// FEMorph Adapt's core (thesis chapter 3) on the case of thesis 3.7.2: a
// 3x5x1-cube object in a 20x20x50 grid of cubes (12 tets each, jittered),
// moving 0.1 along z and turning 1 degree about x through its centre per
// step; a long rotation in place (900 steps of 1 degree); and the contact
// case of thesis 3.7.3: a cylinder translated 1 per step along its axis into
// a half tube of the same radius (CylinderHalfTube::benchmark()).
//
//   bench_adapt [--cells=20,20,50] [--object=3,5,1] [--steps=360]
//               [--rotation-steps=900] [--no-rotation] [--no-peer]
//               [--peer-steps=10] [--every=36]
//               [--contact-steps=45] [--contact-peer-steps=3] [--no-contact]
//               [--contact-only] [--assembly-steps=36] [--no-assembly]
//               [--assembly-only]
//
// Prints every --every steps a row (step, vertices, tets, min and mean
// stretch, region tets, sub-steps, ms), then per case: the median s/step, the
// minimum stretch over all steps against the input's, the vertex drift; and
// the peer measured in the same command: Gmsh re-meshing the exact geometry
// of sampled steps (adapt_gmsh_peer.py), its s/step and the fraction of
// vertices that keep their position (Adapt keeps every vertex outside the
// deformed regions).
//
// 3.7.3 prints every step: the time and its parts, the minimum stretch, the
// vertices, the area of the faces shared by the cylinder and the tube
// against the expected discrete contact area (cylinder_half_tube_contact_area),
// and checks after each step (outside the step's time) that the area is
// within 1%, that no cylinder face lying on the tube's inner surface is
// missing from the tube (a non-conformal contact) and that the mesh is valid
// (check_validity: no inverted or degenerate tet); failures print as FAIL
// lines, a refused step as STEP n REFUSED with AdaptSession's message (the
// case stops there). Then the median time of each part of a step, and the
// Gmsh peer re-meshing the cylinder, half tube and box from OpenCASCADE
// geometry at --contact-peer-steps consecutive steps.
//
// Thesis 3.7.4, the assembly mode: a crank and a bearing meshed separately
// (non-conforming, no space mesh; CrankAssembly::benchmark(), about the
// thesis' 25k tets), the crank turning 10 degrees per step about its axis
// for --assembly-steps steps. Each step prints its time and parts, the
// minimum stretch, the vertices and the contact faces; after each (outside
// its time) the contact is checked conformal (assembly_conformity: crank
// faces lying on the bore that are no bearing faces) and the mesh valid.
#include "adapt/adapt.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "test_adapt_meshes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

using namespace femorph;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::array<int, 3> parse3(const char* s) {
  std::array<int, 3> a{{0, 0, 0}};
  std::sscanf(s, "%d,%d,%d", &a[0], &a[1], &a[2]);
  return a;
}

struct CaseResult {
  double median_step = NAN, min_stretch = 1, input_min = 0, drift = 0, kept = 0, kept_step = 0;
  int steps = 0;
  std::string error;
};

CaseResult run_case(const char* name, const testing::MaterialMesh& in, const RigidMotion& motion, int steps,
                    int every) {
  CaseResult r;
  AdaptSession session;
  const auto t0 = std::chrono::steady_clock::now();
  Status s = session.init(in.points, in.tets, in.material, motion, {});
  const double t_init = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!s) {
    r.error = s.message;
    return r;
  }
  const AdaptStepReport r0 = session.initial_report();
  r.input_min = r0.min_stretch;
  std::printf("\n%s: %zu vertices, %zu tets, input min stretch %.4f mean %.4f, set-up %.3f s\n", name, r0.vertices,
              r0.tets, r0.min_stretch, r0.mean_stretch, t_init);
  std::printf("%6s %9s %9s %8s %8s %9s %5s %9s\n", "step", "vertices", "tets", "min st", "mean st", "region", "sub",
              "ms");
  std::vector<double> times, kept_per_step;
  double part[5] = {0, 0, 0, 0, 0};
  double worst_drift = 0;
  for (int n = 1; n <= steps; ++n) {
    AdaptStepReport rep;
    s = session.advance(&rep);
    if (!s) {
      r.error = s.message;
      break;
    }
    times.push_back(rep.seconds);
    kept_per_step.push_back(1 - std::min(1.0, double(rep.moved_vertices) / double(rep.vertices)));
    part[0] += rep.seconds_region;
    part[1] += rep.seconds_submesh;
    part[2] += rep.seconds_embed;
    part[3] += rep.seconds_improve;
    part[4] += rep.seconds_splice;
    r.min_stretch = std::min(r.min_stretch, rep.min_stretch);
    worst_drift = std::max(worst_drift, std::abs(double(rep.vertices) / double(r0.vertices) - 1));
    if (n % every == 0 || n == steps)
      std::printf("%6d %9zu %9zu %8.4f %8.4f %9zu %5d %9.2f\n", n, rep.vertices, rep.tets, rep.min_stretch,
                  rep.mean_stretch, rep.deformed_region_tets, rep.substeps, 1e3 * rep.seconds);
    r.steps = n;
  }
  if (std::getenv("FEMORPH_ADAPT_WORST")) {
    const AdaptOutput o = session.output();
    std::vector<char> on_object(o.points.size(), 0);
    for (std::size_t t = 0; t < o.tets.size(); ++t)
      if (o.material[t] != 0)
        for (const index_t v : o.tets[t]) on_object[v] = 1;
    std::vector<std::pair<double, std::size_t>> worst;
    for (std::size_t t = 0; t < o.tets.size(); ++t) {
      const Tet& T = o.tets[t];
      const Vec3 g = 0.25 * (o.points[T[0]] + o.points[T[1]] + o.points[T[2]] + o.points[T[3]]);
      if ((g - motion.pose(r.steps).apply(motion.rotation_center)).norm() > 7) continue;
      worst.emplace_back(tet_stretch(o.points[T[0]], o.points[T[1]], o.points[T[2]], o.points[T[3]]), t);
    }
    std::sort(worst.begin(), worst.end());
    const Vec3 c = motion.pose(r.steps).apply(motion.rotation_center);
    for (std::size_t i = 0; i < 12 && i < worst.size(); ++i) {
      const Tet& T = o.tets[worst[i].second];
      int n = 0;
      for (const index_t v : T) n += on_object[v];
      const Vec3 g = 0.25 * (o.points[T[0]] + o.points[T[1]] + o.points[T[2]] + o.points[T[3]]);
      std::printf("worst %.3f material %d object vertices %d distance from object centre %.2f\n", worst[i].first,
                  o.material[worst[i].second], n, (g - c).norm());
    }
  }
  r.median_step = median(times);
  r.kept_step = median(kept_per_step);
  if (r.steps > 0)
    std::printf("mean ms/step by part: region %.2f, submesh %.2f, embedding %.2f, improvement %.2f, splice %.2f\n",
                1e3 * part[0] / r.steps, 1e3 * part[1] / r.steps, 1e3 * part[2] / r.steps, 1e3 * part[3] / r.steps,
                1e3 * part[4] / r.steps);
  r.drift = worst_drift;
  // Vertices of the input still at their input position (or moved rigidly
  // with the object) at the end.
  const AdaptOutput out = session.output();
  std::size_t kept = 0;
  for (std::size_t v = 0; v < out.points.size(); ++v) {
    const VertexStencil& o = out.point_origin[v];
    if (o.ids[0] >= 0 && o.weights[0] == 1 && (out.points[v] - in.points[o.ids[0]]).norm() == 0) ++kept;
  }
  r.kept = double(kept) / double(in.points.size());
  std::printf("%s: %d steps, median %.2f ms/step, min stretch over all steps %.4f (input %.4f), vertex drift "
              "%.2f%%, vertices that keep their position in a step %.1f%% (median), at their input position at "
              "the end %.1f%%%s%s\n",
              name, r.steps, 1e3 * r.median_step, r.min_stretch, r.input_min, 100 * r.drift, 100 * r.kept_step,
              100 * r.kept, r.error.empty() ? "" : "; stopped: ", r.error.c_str());
  return r;
}


// ---- Thesis 3.7.4: an assembly, no space mesh ------------------------------

struct AssemblyResult {
  CaseResult base;
  int conformity_failures = 0, validity_failures = 0, area_failures = 0;
  std::size_t input_vertices = 0, final_vertices = 0;
};

AssemblyResult run_assembly_case(const testing::CrankAssembly& g, int steps) {
  AssemblyResult r;
  Status st;
  const auto t0 = std::chrono::steady_clock::now();
  const testing::MaterialMesh in = testing::make_crank_assembly(g, &st);
  const double t_make = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!st) {
    r.base.error = "make_crank_assembly: " + st.message;
    std::printf("\n3.7.4: %s\n", r.base.error.c_str());
    return r;
  }
  RigidMotion motion;
  motion.rotation_axis = Vec3::UnitZ();
  motion.rotation_degrees_per_step = 10;
  AdaptSession session;
  const auto t1 = std::chrono::steady_clock::now();
  Status s = session.init(in.points, in.tets, in.material, motion, {});
  const double t_init = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  if (!s) {
    r.base.error = s.message;
    std::printf("\n3.7.4 crank assembly: AdaptSession::init failed: %s\n", s.message.c_str());
    return r;
  }
  const AdaptStepReport r0 = session.initial_report();
  r.base.input_min = r0.min_stretch;
  r.input_vertices = r0.vertices;
  std::printf("\n3.7.4 crank assembly (no space mesh, non-conforming): r %g, R %g, crank length %g, bearing length "
              "%g, %d and %d segments; %zu vertices, %zu tets (made in %.1f s), input min stretch %.4f mean %.4f, "
              "set-up %.3f s\n",
              g.r, g.R, g.Lc, g.Lb, g.n_crank, g.n_bearing, r0.vertices, r0.tets, t_make, r0.min_stretch,
              r0.mean_stretch, t_init);
  std::printf("%5s %9s %9s %8s %8s %8s %9s %9s %8s %8s %8s\n", "step", "vertices", "tets", "min st", "mean st",
              "contact", "area", "expected", "s", "zone s", "impr s");
  std::vector<double> times;
  std::vector<double> part[7];
  const double edge = std::min(g.crank_edge(), g.bearing_edge());
  for (int n = 1; n <= steps; ++n) {
    AdaptStepReport rep;
    s = session.advance(&rep);
    if (!s) {
      r.base.error = s.message;
      std::printf("STEP %d REFUSED: %s\n", n, s.message.c_str());
      break;
    }
    times.push_back(rep.seconds);
    const double parts[6] = {rep.seconds_region, rep.seconds_submesh, rep.seconds_embed,
                             rep.seconds_contact, rep.seconds_improve, rep.seconds_splice};
    double rest = rep.seconds;
    for (int k = 0; k < 6; ++k) {
      part[k].push_back(parts[k]);
      rest -= parts[k];
    }
    part[6].push_back(rest);
    r.base.min_stretch = std::min(r.base.min_stretch, rep.min_stretch);
    r.base.drift = std::max(r.base.drift, std::abs(double(rep.vertices) / double(r0.vertices) - 1));
    r.final_vertices = rep.vertices;
    const AdaptOutput o = session.output();
    const testing::AssemblyConformity c = testing::assembly_conformity(o, g.r, 0.1 * edge, 0.05 * edge);
    const bool valid = check_validity(o.points, o.tets).ok();
    const bool area_ok = std::abs(c.shared_area - g.contact_area()) <= 0.01 * g.contact_area();
    r.conformity_failures += c.coincident > 0;
    r.validity_failures += !valid;
    r.area_failures += !area_ok;
    std::printf("%5d %9zu %9zu %8.4f %8.4f %8zu %9.4f %9.4f %8.3f %8.3f %8.3f%s%s%s\n", n, rep.vertices, rep.tets,
                rep.min_stretch, rep.mean_stretch, c.shared, c.shared_area, g.contact_area(), rep.seconds,
                rep.seconds_contact, rep.seconds_improve, c.coincident ? "  FAIL non-conformal" : "",
                valid ? "" : "  FAIL invalid", area_ok ? "" : "  FAIL area");
    r.base.steps = n;
    if (std::getenv("FEMORPH_ADAPT_WORST") && rep.min_stretch < 0.07) {
      std::vector<std::pair<double, std::size_t>> worst;
      for (std::size_t t = 0; t < o.tets.size(); ++t) {
        const Tet& T = o.tets[t];
        worst.emplace_back(tet_stretch(o.points[T[0]], o.points[T[1]], o.points[T[2]], o.points[T[3]]), t);
      }
      std::sort(worst.begin(), worst.end());
      for (std::size_t i = 0; i < 4; ++i) {
        const Tet& T = o.tets[worst[i].second];
        std::printf("  worst %.3f material %d:", worst[i].first, o.material[worst[i].second]);
        for (const index_t v : T) {
          const Vec3& p = o.points[v];
          std::printf(" (rho %.4f th %.1f z %.3f)", std::hypot(p.x(), p.y()), std::atan2(p.y(), p.x()) * 180 / kPi,
                      p.z());
        }
        std::printf("\n");
      }
    }
  }
  r.base.median_step = median(times);
  if (!times.empty())
    std::printf("median s/step by part: region %.3f, submesh %.3f, embedding %.3f, contact zone (merge, refill) "
                "%.3f, improvement %.3f, splice %.3f, rest (overlap check, contact detection, step set-up) %.3f\n",
                median(part[0]), median(part[1]), median(part[2]), median(part[3]), median(part[4]), median(part[5]),
                median(part[6]));
  std::printf("3.7.4 crank assembly: %d of %d steps, median %.3f s/step, min stretch over all steps %.4f (input "
              "%.4f), vertices %zu -> %zu (largest drift %.2f%%), non-conformal contact in %d steps, contact area "
              "off by > 1%% in %d steps, invalid mesh in %d steps%s%s\n",
              r.base.steps, steps, r.base.median_step, r.base.min_stretch, r.base.input_min, r.input_vertices,
              r.final_vertices, 100 * r.base.drift, r.conformity_failures, r.area_failures, r.validity_failures,
              r.base.error.empty() ? "" : "; STOPPED: ", r.base.error.c_str());
  return r;
}

// ---- Thesis 3.7.3: a cylinder into a half tube, with contact ---------------

struct FaceKeyHash {
  std::size_t operator()(const std::array<index_t, 3>& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (const index_t v : k) h = (h ^ static_cast<std::uint32_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};
using FaceCount = std::unordered_map<std::array<index_t, 3>, int, FaceKeyHash>;

std::array<index_t, 3> face_key(const Tet& t, int f) {
  std::array<index_t, 3> k{{t[kTetFace[f][0]], t[kTetFace[f][1]], t[kTetFace[f][2]]}};
  std::sort(k.begin(), k.end());
  return k;
}

double tri_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

/// The contact of an output: the faces shared by a tet of `a` and one of
/// `b` (their area), and the faces of a's surface that lie on b's surface by
/// position (`on_other`: the contact surface by geometry) but are no face of
/// b's (non-conformal contact).
struct ContactCheck {
  double area = 0;
  std::size_t shared = 0, unmatched = 0;
  double unmatched_area = 0;
};

ContactCheck check_contact(const AdaptOutput& o, int a, int b, const std::function<bool(const Vec3&)>& on_other) {
  FaceCount fa;
  fa.reserve(o.tets.size());
  for (std::size_t t = 0; t < o.tets.size(); ++t)
    if (o.material[t] == a)
      for (int f = 0; f < 4; ++f) ++fa[face_key(o.tets[t], f)];
  ContactCheck c;
  FaceCount shared;
  for (std::size_t t = 0; t < o.tets.size(); ++t)
    if (o.material[t] == b)
      for (int f = 0; f < 4; ++f) {
        const auto k = face_key(o.tets[t], f);
        const auto it = fa.find(k);
        if (it == fa.end() || it->second != 1) continue;
        ++shared[k];
        c.area += tri_area(o.points[k[0]], o.points[k[1]], o.points[k[2]]);
      }
  c.shared = shared.size();
  for (const auto& [k, n] : fa) {
    if (n != 1 || shared.count(k)) continue;
    const Vec3 g = (o.points[k[0]] + o.points[k[1]] + o.points[k[2]]) / 3;
    if (!on_other(g)) continue;
    ++c.unmatched;
    c.unmatched_area += tri_area(o.points[k[0]], o.points[k[1]], o.points[k[2]]);
  }
  return c;
}

/// The mean edge of an equilateral triangle of the mean area of the
/// boundary faces of the tets of material `m` (-1: the whole mesh's outer
/// boundary), the size a re-mesher needs for as many surface triangles.
double surface_size(const testing::MaterialMesh& in, int m) {
  FaceCount count;
  for (std::size_t t = 0; t < in.tets.size(); ++t)
    if (m < 0 || in.material[t] == m)
      for (int f = 0; f < 4; ++f) ++count[face_key(in.tets[t], f)];
  double area = 0;
  std::size_t n = 0;
  for (const auto& [k, c] : count)
    if (c == 1) {
      area += tri_area(in.points[k[0]], in.points[k[1]], in.points[k[2]]);
      ++n;
    }
  return n ? std::sqrt(4 / std::sqrt(3.0) * area / static_cast<double>(n)) : NAN;
}

/// Per material (0 space, 1 cylinder, 2 tube): the minimum stretch and the
/// tets below 0.1, as "space 0.0271 (12 < 0.1), ...".
std::string stretch_by_material(const std::vector<Vec3>& p, const std::vector<Tet>& tets,
                                const std::vector<int>& material) {
  double lo[3] = {1, 1, 1};
  std::size_t below[3] = {0, 0, 0};
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const int m = material[t];
    if (m < 0 || m > 2) continue;
    const double q = tet_stretch(p[tets[t][0]], p[tets[t][1]], p[tets[t][2]], p[tets[t][3]]);
    lo[m] = std::min(lo[m], q);
    below[m] += q < 0.1;
  }
  static const char* names[3] = {"space", "cylinder", "tube"};
  std::string out;
  for (int m = 0; m < 3; ++m) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s%s %.4f (%zu tets < 0.1)", m ? ", " : "", names[m], lo[m], below[m]);
    out += buf;
  }
  return out;
}

struct ContactResult {
  CaseResult base;
  double drift_final = 0, worst_area_error = 0;
  int area_failures = 0, validity_failures = 0, conformity_failures = 0;
  std::size_t input_tets = 0;
};

ContactResult run_contact_case(const testing::CylinderHalfTube& g, const testing::MaterialMesh& in, int steps) {
  ContactResult r;
  CaseResult& b = r.base;
  RigidMotion motion;
  motion.translation_per_step = Vec3(0, 0, 1);
  AdaptOptions options;
  options.moving_object = 1;
  AdaptSession session;
  const auto t0 = std::chrono::steady_clock::now();
  Status s = session.init(in.points, in.tets, in.material, motion, options);
  const double t_init = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!s) {
    b.error = "init: " + s.message;
    std::printf("\n3.7.3 cylinder into half tube: AdaptSession::init failed: %s\n", s.message.c_str());
    return r;
  }
  const AdaptStepReport r0 = session.initial_report();
  b.input_min = r0.min_stretch;
  r.input_tets = r0.tets;
  std::printf("\n3.7.3 cylinder into half tube: %zu vertices, %zu tets, input min stretch %.4f mean %.4f, set-up "
              "%.3f s; translation (0, 0, 1) per step, %d steps (front cap from %.2f to %.2f; tube z in [0, %g])\n",
              r0.vertices, r0.tets, r0.min_stretch, r0.mean_stretch, t_init, steps, -g.gap, steps - g.gap, g.Lt);
  std::printf("%5s %8s %8s %8s %8s %7s %4s %8s %9s %9s %8s %6s %7s %7s %7s %7s %7s %7s\n", "step", "vertices",
              "tets", "min st", "mean st", "region", "sub", "s", "contact", "expected", "err %", "kept%", "reg s",
              "sub s", "emb s", "cont s", "impr s", "spl s");
  std::printf("input min stretch by material: %s\n", stretch_by_material(in.points, in.tets, in.material).c_str());
  const double sag = g.r * (1 - std::cos(kPi / g.n_theta));
  std::vector<double> times, kept_per_step, part[7];
  for (int n = 1; n <= steps; ++n) {
    AdaptStepReport rep;
    s = session.advance(&rep);
    if (!s) {
      b.error = s.message;
      std::printf("STEP %d REFUSED (AdaptSession::advance failed): %s\n", n, s.message.c_str());
      break;
    }
    times.push_back(rep.seconds);
    const double kept = 1 - std::min(1.0, double(rep.moved_vertices) / double(rep.vertices));
    kept_per_step.push_back(kept);
    const double parts[6] = {rep.seconds_region,  rep.seconds_submesh, rep.seconds_embed,
                             rep.seconds_contact, rep.seconds_improve, rep.seconds_splice};
    double sum = 0;
    for (int i = 0; i < 6; ++i) {
      part[i].push_back(parts[i]);
      sum += parts[i];
    }
    part[6].push_back(rep.seconds - sum);
    b.min_stretch = std::min(b.min_stretch, rep.min_stretch);
    const double drift = double(rep.vertices) / double(r0.vertices) - 1;
    b.drift = std::max(b.drift, std::abs(drift));
    r.drift_final = drift;
    b.steps = n;
    // The checks (outside the step's time): the contact area against the
    // discrete expectation, the contact conformal (no cylinder face lying on
    // the tube's inner surface that is not a tube face too), a valid mesh.
    const AdaptOutput o = session.output();
    const double z_shift = n * 1.0;
    const auto on_tube = [&](const Vec3& p) {
      // The cylinder face's centroid on the tube's inner polygon: y < 0,
      // z inside the tube, radius within the chord sag of r.
      const double rho = std::hypot(p.x(), p.y());
      return p.y() < -1e-6 * g.r && p.z() > 1e-9 && p.z() < g.Lt - 1e-9 && rho <= g.r + 1e-6 * g.r &&
             rho >= g.r - sag - 1e-6 * g.r;
    };
    const ContactCheck c = check_contact(o, 1, 2, on_tube);
    const testing::ContactArea expected = testing::cylinder_half_tube_contact_area(g, z_shift);
    const double err = expected.discrete > 0 ? c.area / expected.discrete - 1 : (c.area > 0 ? INFINITY : 0);
    r.worst_area_error = std::max(r.worst_area_error, std::abs(err));
    const ValidityReport v = check_validity(o.points, o.tets);
    std::printf("%5d %8zu %8zu %8.4f %8.4f %7zu %4d %8.3f %9.3f %9.3f %8.3f %6.1f %7.3f %7.3f %7.3f %7.3f %7.3f "
                  "%7.3f\n",
                  n, rep.vertices, rep.tets, rep.min_stretch, rep.mean_stretch, rep.deformed_region_tets,
                  rep.substeps, rep.seconds, c.area, expected.discrete, 100 * err, 100 * kept, rep.seconds_region,
                  rep.seconds_submesh, rep.seconds_embed, rep.seconds_contact, rep.seconds_improve,
                  rep.seconds_splice);
    if (std::abs(err) > 0.01) {
      ++r.area_failures;
      std::printf("  FAIL step %d: contact area %.4f vs expected %.4f (discrete; exact %.4f): %+.3f%% (> 1%%), %zu "
                  "shared faces\n",
                  n, c.area, expected.discrete, expected.exact, 100 * err, c.shared);
    }
    if (c.unmatched) {
      ++r.conformity_failures;
      std::printf("  FAIL step %d: %zu cylinder faces (area %.4f) on the tube's inner surface are not tube faces\n",
                  n, c.unmatched, c.unmatched_area);
    }
    if (!v.ok()) {
      ++r.validity_failures;
      std::printf("  FAIL step %d: invalid mesh: %s\n", n, v.summary().c_str());
    }
    for (const std::string& w : rep.warnings) std::printf("  warning step %d: %s\n", n, w.c_str());
    std::fflush(stdout);
  }
  b.median_step = median(times);
  b.kept_step = median(kept_per_step);
  if (b.steps > 0) {
    const AdaptOutput o = session.output();
    std::printf("step %d min stretch by material: %s\n", b.steps,
                stretch_by_material(o.points, o.tets, o.material).c_str());
  }
  if (b.steps > 0)
    std::printf("median s/step by part: region %.3f, submesh %.3f, embedding %.3f, contact %.3f, improvement %.3f, "
                "splice %.3f, rest (penetration walk, contact detection, step set-up) %.3f; total %.3f\n",
                median(part[0]), median(part[1]), median(part[2]), median(part[3]), median(part[4]), median(part[5]),
                median(part[6]), b.median_step);
  std::printf("3.7.3 cylinder into half tube: %d of %d steps, median %.3f s/step, min stretch over all steps %.4f "
              "(input %.4f), vertex drift max %.2f%% final %+.2f%%, contact area worst error %.3f%% (%d steps over "
              "1%%), non-conformal contact in %d steps, invalid mesh in %d steps, vertices that keep their "
              "position in a step %.1f%% (median)%s%s\n",
              b.steps, steps, b.median_step, b.min_stretch, b.input_min, 100 * b.drift, 100 * r.drift_final,
              100 * r.worst_area_error, r.area_failures, r.conformity_failures, r.validity_failures,
              100 * b.kept_step, b.error.empty() ? "" : "; STOPPED: ", b.error.c_str());
  return r;
}

/// Runs adapt_gmsh_peer.py with `args`, echoing its output; its median s/step.
double run_peer(const std::string& args) {
  const std::string script = std::string(FEMORPH_BENCH_DIR) + "/adapt_gmsh_peer.py";
  if (!std::filesystem::exists(script)) {
    std::printf("\ngmsh peer: %s not found, left out\n", script.c_str());
    return NAN;
  }
  const std::string cmd = "/usr/bin/python3 " + script + " " + args + " 2>&1";
  std::printf("\ngmsh peer: %s\n", cmd.c_str());
  std::fflush(stdout);
  double peer_step = NAN;
  FILE* p = popen(cmd.c_str(), "r");
  char line[4096];
  while (p && std::fgets(line, sizeof line, p)) {
    std::fputs(line, stdout);
    double x;
    if (std::sscanf(line, "median s/step %lf", &x) == 1) peer_step = x;
  }
  if (p && pclose(p) != 0) std::printf("gmsh peer: exited with an error\n");
  std::fflush(stdout);
  return peer_step;
}

}  // namespace

int main(int argc, char** argv) {
  std::array<int, 3> cells{{20, 20, 50}}, object{{3, 5, 1}};
  int steps = 360, rotation_steps = 900, every = 36, peer_steps = 10, contact_steps = 45, contact_peer_steps = 3;
  int assembly_steps = 36;
  bool block = true, rotation = true, peer = true, contact = true, assembly = true;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--cells=", 8) == 0) cells = parse3(argv[i] + 8);
    else if (std::strncmp(argv[i], "--object=", 9) == 0) object = parse3(argv[i] + 9);
    else if (std::strncmp(argv[i], "--steps=", 8) == 0) steps = std::atoi(argv[i] + 8);
    else if (std::strncmp(argv[i], "--rotation-steps=", 17) == 0) rotation_steps = std::atoi(argv[i] + 17);
    else if (std::strncmp(argv[i], "--every=", 8) == 0) every = std::max(1, std::atoi(argv[i] + 8));
    else if (std::strncmp(argv[i], "--peer-steps=", 13) == 0) peer_steps = std::atoi(argv[i] + 13);
    else if (std::strncmp(argv[i], "--contact-steps=", 16) == 0) contact_steps = std::atoi(argv[i] + 16);
    else if (std::strncmp(argv[i], "--contact-peer-steps=", 21) == 0) contact_peer_steps = std::atoi(argv[i] + 21);
    else if (std::strcmp(argv[i], "--no-rotation") == 0) rotation = false;
    else if (std::strcmp(argv[i], "--no-peer") == 0) peer = false;
    else if (std::strcmp(argv[i], "--no-contact") == 0) contact = false;
    else if (std::strcmp(argv[i], "--contact-only") == 0) block = rotation = assembly = false;
    else if (std::strncmp(argv[i], "--assembly-steps=", 17) == 0) assembly_steps = std::atoi(argv[i] + 17);
    else if (std::strcmp(argv[i], "--no-assembly") == 0) assembly = false;
    else if (std::strcmp(argv[i], "--assembly-only") == 0) block = rotation = contact = false;
    else {
      std::fprintf(stderr,
                   "usage: %s [--cells=20,20,50] [--object=3,5,1] [--steps=360] [--rotation-steps=900] "
                   "[--every=36] [--peer-steps=10] [--no-rotation] [--no-peer] [--contact-steps=45] "
                   "[--contact-peer-steps=3] [--no-contact] [--contact-only] [--assembly-steps=36] "
                   "[--no-assembly] [--assembly-only]\n",
                   argv[0]);
      return 2;
    }
  }
  contact = contact && contact_steps > 0;
  CaseResult a, b;
  double peer_step = NAN;
  if (block) {
    // The object starts low enough in z for its translation (0.1 per step)
    // to end as far from the other end.
    const int travel = static_cast<int>(std::ceil(0.1 * steps));
    const int z0 = std::max(0, (cells[2] - object[2] - travel) / 2);
    const testing::MaterialMesh in = testing::make_block_in_box(cells, object, 1.0, 0.15, 1, {{-1, -1, z0}}, 1);
    RigidMotion motion;
    motion.translation_per_step = Vec3(0, 0, 0.1);
    motion.rotation_axis = Vec3(1, 0, 0);
    motion.rotation_center = 0.5 * (in.object_lo + in.object_hi);
    motion.rotation_degrees_per_step = 1;
    a = run_case("3.7.2 translate + rotate", in, motion, steps, every);
    if (rotation) {
      RigidMotion spin;
      spin.rotation_axis = Vec3(1, 0, 0);
      spin.rotation_center = motion.rotation_center;
      spin.rotation_degrees_per_step = 1;
      b = run_case("rotation in place", in, spin, rotation_steps, std::max(every, rotation_steps / 10));
    }
    if (peer) {
      char args[512];
      std::snprintf(args, sizeof args, "--cells %d %d %d --object %d %d %d --steps %d --stride %d", cells[0],
                    cells[1], cells[2], object[0], object[1], object[2], peer_steps,
                    std::max(1, steps / std::max(1, peer_steps)));
      peer_step = run_peer(args);
    }
  }

  // Thesis 3.7.3: the cylinder (material 1) moves 1 per step along its axis
  // into the half tube (material 2); the generator's box holds the travel of
  // the --contact-steps steps (its front cap from -gap to steps - gap).
  ContactResult c;
  double contact_peer_step = NAN;
  if (contact) {
    testing::CylinderHalfTube g = testing::CylinderHalfTube::benchmark();
    g.travel = std::max(g.planned_travel(), static_cast<double>(contact_steps));
    Status st;
    const auto t0 = std::chrono::steady_clock::now();
    const testing::MaterialMesh in = testing::make_cylinder_half_tube(g, &st);
    const double t_make = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!st) {
      c.base.error = "make_cylinder_half_tube: " + st.message;
      std::printf("\n3.7.3: %s\n", c.base.error.c_str());
    } else {
      const double size_object = surface_size(in, 1), size_box = surface_size(in, -1);
      std::printf("\n3.7.3 mesh: r %g, R %g, cylinder length %g, tube length %g, gap %g, n_theta %d, margin %g, "
                  "travel %g; %zu points, %zu tets (made in %.1f s); surface size (equilateral edge of the mean "
                  "triangle) %.3f on the cylinder, %.3f on the box\n",
                  g.r, g.R, g.Lc, g.Lt, g.gap, g.n_theta, g.margin, g.travel, in.points.size(), in.tets.size(),
                  t_make, size_object, size_box);
      c = run_contact_case(g, in, contact_steps);
      if (peer && contact_peer_steps > 0) {
        // Consecutive steps in the middle of the path (the cylinder well
        // inside the tube), after an untimed first one for the kept vertices.
        const int first = std::max(1, contact_steps / 2);
        char args[768];
        std::snprintf(args, sizeof args,
                      "--case cylinder-half-tube --r %.17g --R %.17g --Lc %.17g --Lt %.17g --gap %.17g "
                      "--margin %.17g --travel %.17g --translation 1 --size %.6g --size-box %.6g "
                      "--first-step %d --steps %d --stride 1 --target-tets %zu",
                      g.r, g.R, g.Lc, g.Lt, g.gap, g.margin, g.travel, size_object, size_box, first - 1,
                      contact_peer_steps, in.tets.size());
        contact_peer_step = run_peer(args);
      }
    }
  }

  // Thesis 3.7.4: the assembly (no space mesh).
  AssemblyResult asm_result;
  assembly = assembly && assembly_steps > 0;
  if (assembly) asm_result = run_assembly_case(testing::CrankAssembly::benchmark(), assembly_steps);

  std::printf("\nsummary (goals: 3.7.2: min stretch >= input's, drift <= 3%% (rotation: 5%%), <= 20 ms/step; "
              "3.7.3: min stretch >= 0.1 (thesis 0.056), drift <= 10%%, contact area within 1%%, <= 0.5 s/step "
              "(thesis 4.5); 3.7.4: conformal contact every step, <= 0.5 s/step (thesis 4.6))\n");
  std::printf("%-18s %10s %12s %10s %9s %14s\n", "case", "ms/step", "min stretch", "input min", "drift %",
              "kept/step %");
  if (block)
    std::printf("%-18s %10.2f %12.4f %10.4f %9.2f %14.1f\n", "translate+rotate", 1e3 * a.median_step, a.min_stretch,
                a.input_min, 100 * a.drift, 100 * a.kept_step);
  if (rotation)
    std::printf("%-18s %10.2f %12.4f %10.4f %9.2f %14.1f\n", "rotation", 1e3 * b.median_step, b.min_stretch,
                b.input_min, 100 * b.drift, 100 * b.kept_step);
  if (block && !std::isnan(peer_step))
    std::printf("%-18s %10.2f %12s %10s %9s %14s   Adapt %.0fx faster per step\n", "gmsh re-mesh", 1e3 * peer_step,
                "(below)", "", "", "(below)", peer_step / a.median_step);
  if (contact) {
    const CaseResult& k = c.base;
    std::printf("%-18s %10.2f %12.4f %10.4f %9.2f %14.1f   %d/%d steps, final drift %+.2f%%, contact area worst "
                "error %.3f%% (%d steps > 1%%), non-conformal contact %d steps, invalid %d steps%s%s\n",
                "cylinder+tube", 1e3 * k.median_step, k.min_stretch, k.input_min, 100 * k.drift, 100 * k.kept_step,
                k.steps, contact_steps, 100 * c.drift_final, 100 * c.worst_area_error, c.area_failures,
                c.conformity_failures, c.validity_failures, k.error.empty() ? "" : "; STOPPED: ", k.error.c_str());
    if (!std::isnan(contact_peer_step))
      std::printf("%-18s %10.2f %12s %10s %9s %14s   Adapt %.1fx faster per step\n", "gmsh re-mesh (3.7.3)",
                  1e3 * contact_peer_step, "(above)", "", "", "(above)", contact_peer_step / k.median_step);
  }
  if (assembly) {
    const CaseResult& k = asm_result.base;
    const bool met = k.error.empty() && asm_result.conformity_failures == 0 && asm_result.validity_failures == 0 &&
                     k.median_step <= 0.5;
    std::printf("%-18s %10.2f %12.4f %10.4f %9.2f %14s   %d/%d steps, vertices %zu -> %zu, non-conformal contact %d "
                "steps, contact area > 1%% off %d steps, invalid %d steps: %s%s%s\n",
                "crank assembly", 1e3 * k.median_step, k.min_stretch, k.input_min, 100 * k.drift, "-", k.steps,
                assembly_steps, asm_result.input_vertices, asm_result.final_vertices, asm_result.conformity_failures,
                asm_result.area_failures, asm_result.validity_failures, met ? "met" : "NOT met",
                k.error.empty() ? "" : "; STOPPED: ", k.error.c_str());
  }
  const bool assembly_ok = !assembly || (asm_result.base.error.empty() && asm_result.conformity_failures == 0 &&
                                         asm_result.validity_failures == 0);
  const bool contact_ok = !contact || (c.base.error.empty() && c.area_failures == 0 && c.conformity_failures == 0 &&
                                       c.validity_failures == 0);
  return a.error.empty() && b.error.empty() && contact_ok && assembly_ok ? 0 : 1;
}
