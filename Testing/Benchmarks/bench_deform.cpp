// Benchmark of FEMorph Deform's core (thesis 2.5, Core/deform): the boss
// height of boss_block changed 15 -> 20 (Distance on the boss top: the plane
// region at z = 35 with normal +z, found in the segmentation).
//
//   build/bin/bench_deform [--runs=5] [--deform-runs=3] [--param-triangles=95000]
//                          [--deform-triangles=115000] [--inner=5000] [--no-peer] [--no-deform] [--no-param]
//                          [--no-whole] [--cpu]
//
// Parts: boss_block made with Data/generate_parts.py --fine at about
// --param-triangles boundary triangles (about 110,000 vertices: the whole-mesh
// parameterisation, the thesis' 94,706-vertex case) and at about
// --deform-triangles (about 700,000 tets: deform + improve against Gmsh),
// into <build>/bench-data/deform/t<N>/ on first use (reused afterwards).
// Each part is read with VTK and segmented once with femorph::segment_boundary
// (vtkFEMorphSegmentationArrays::SegmentMesh, FEMorph Segment's defaults).
//
// Rows (medians of --runs runs; the goals are printed beside them):
//  - parameterize_vertices with an empty deformable mask (the whole mesh;
//    --no-whole skips it);
//  (--cpu: the rows in process CPU seconds instead of wall seconds, to
//  compare two versions with OMP_NUM_THREADS=1 on a machine others load);
//  - parameterize_vertices of a local region: extract_deformable_region with
//    the reach (found by bisection) that gives about --inner inner unknowns;
//    the same for the hole's radius 6 -> 7 (a feature small enough for a
//    local region of the goal's size), its repositioning over a sweep of
//    at least ten new targets;
//  - update_region_surfaces + reposition_vertices for a new target on that
//    parameterisation, with its solve history (superposition, as
//    DeformSession repositions) and without (every target solved);
//  - deform_mesh with improve on (median of --deform-runs runs, a fresh copy
//    of the segmented mesh each run), against the peer measured in the same
//    command: Gmsh meshing the changed CAD (boss_height 20) at the part's
//    size scale with the same options (gmsh_remesh_peer.py; only Gmsh's
//    surface and volume meshing timed, with as many threads as FEMorph has);
//  - peak memory: the process's peak resident set (VmHWM, reset through
//    /proc/self/clear_refs before each measured call) above its resident set
//    just before the call, per tet; and the process peak per tet.
#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphSegmentationArrays.h"

#include "common/parallel.h"
#include "deform/deform.h"
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"

#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

using femorph::index_t;
using femorph::Vec3;
using Clock = std::chrono::steady_clock;
using json = nlohmann::json;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : v[v.size() / 2];
}

/// Median wall time of `runs` calls of `f`.
/// --cpu: rows timed by the process's CPU time, not wall time (with
/// OMP_NUM_THREADS=1, to compare two versions on a machine others load).
bool g_cpu_time = false;

double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double time_median(int runs, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    const double c0 = g_cpu_time ? cpu_seconds() : 0;
    f();
    t.push_back(g_cpu_time ? cpu_seconds() - c0 : seconds_since(t0));
  }
  return median(t);
}

// ---- memory -----------------------------------------------------------------

/// A field of /proc/self/status in kB (VmRSS, VmHWM); 0 when missing.
long status_kb(const char* field) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const std::size_t n = std::strlen(field);
  while (std::getline(f, line))
    if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':') return std::atol(line.c_str() + n + 1);
  return 0;
}

/// Starts a peak measurement: returns freed heap to the system, resets the
/// peak resident set to the current one (Linux >= 4.0; otherwise the peak
/// stays the process's) and returns the resident set in kB.
long peak_start() {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
  return status_kb("VmRSS");
}

// ---- parts ------------------------------------------------------------------

std::string run_capture(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  pclose(p);
  return out;
}

/// The number after `key ` on its own line of `log` (NaN: none).
double value_of(const std::string& log, const std::string& key) {
  std::istringstream s(log);
  std::string line;
  double v = std::numeric_limits<double>::quiet_NaN();
  while (std::getline(s, line))
    if (line.compare(0, key.size() + 1, key + " ") == 0) v = std::atof(line.c_str() + key.size() + 1);
  return v;
}

/// boss_block_fine.vtu at about `triangles` boundary triangles, made with
/// Gmsh on first use; empty on failure.
std::string fine_part(int triangles) {
  const std::string dir = std::string(FEMORPH_BINARY_DIR) + "/bench-data/deform/t" + std::to_string(triangles);
  const std::string part = dir + "/boss_block_fine.vtu";
  if (std::filesystem::exists(part)) return part;
  std::printf("making boss_block at about %d boundary triangles with Gmsh into %s ...\n", triangles, dir.c_str());
  std::filesystem::create_directories(dir);
  const std::string cmd = std::string("/usr/bin/python3 ") + FEMORPH_DATA_DIR +
                          "/generate_parts.py --fine boss_block --target-boundary-triangles " +
                          std::to_string(triangles) + " --out-dir " + dir + " > " + dir + "/generate.log 2>&1";
  if (std::system(cmd.c_str()) != 0 || !std::filesystem::exists(part)) {
    std::fprintf(stderr, "could not make the part (see %s/generate.log)\n", dir.c_str());
    return {};
  }
  return part;
}

struct Part {
  std::string path;
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  femorph::TetMesh mesh;  ///< with the segmentation's face regions
  femorph::DeformRegions regions;
  index_t boss_top = femorph::kInvalidIndex;
  index_t hole = femorph::kInvalidIndex;  ///< the through hole's cylinder (r 6 at x 75, y 30)
  double size_scale = std::numeric_limits<double>::quiet_NaN();  ///< fine.size_scale of the JSON
  double seconds_segment = 0;
  std::size_t vertices = 0, tets = 0;
};

/// Reads, converts and segments `path`; finds the boss top (plane z = 35, +z).
bool load_part(const std::string& path, Part& part) {
  part.path = path;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  part.grid = reader->GetOutput();
  const femorph::Status built = vtkFEMorphMeshConversion::ToTetMesh(part.grid, femorph::BuildOptions(), part.mesh);
  if (!built) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), built.message.c_str());
    return false;
  }
  vtkSmartPointer<vtkUnstructuredGrid> working;
  vtkFEMorphSegmentationArrays::MeshSegmentation seg;
  std::size_t count = 0;
  const auto t0 = Clock::now();
  const femorph::Status segmented =
    vtkFEMorphSegmentationArrays::SegmentMesh(part.mesh, part.grid, working, seg, count, nullptr);
  part.seconds_segment = seconds_since(t0);
  if (!segmented) {
    std::fprintf(stderr, "%s: segmentation failed: %s\n", path.c_str(), segmented.message.c_str());
    return false;
  }
  part.regions.surfaces = seg.RegionSurfaces;
  part.regions.convexity = seg.RegionConvexity;
  for (std::size_t r = 0; r < part.regions.size(); ++r) {
    const femorph::SurfacePrimitive& s = part.regions.surfaces[r];
    if (s.type == femorph::SurfaceType::Cylinder && std::abs(s.axis.z()) > 0.999 && std::abs(s.radius - 6) < 1e-3 &&
        (Vec3(s.point.x(), s.point.y(), 0) - Vec3(75, 30, 0)).norm() < 1e-3)
      part.hole = static_cast<index_t>(r);
    if (s.type != femorph::SurfaceType::Plane || s.axis.z() < 0.999) continue;
    if (std::abs(s.axis.dot(Vec3(0, 0, 35) - s.point)) < 1e-6) part.boss_top = static_cast<index_t>(r);
  }
  if (part.boss_top < 0) {
    std::fprintf(stderr, "%s: no plane region at z = 35 with normal +z\n", path.c_str());
    return false;
  }
  part.vertices = part.mesh.points().size();
  part.tets = static_cast<std::size_t>(part.grid->GetNumberOfCells());
  std::ifstream f(std::filesystem::path(path).replace_extension(".json"));
  if (f) {
    const json j = json::parse(f, nullptr, false);
    if (!j.is_discarded() && j.contains("fine")) part.size_scale = j["fine"].value("size_scale", part.size_scale);
  }
  return true;
}

femorph::DeformOptions boss_height_options(const Part& part) {
  femorph::DeformOptions o;
  o.type = femorph::DeformationType::Distance;
  o.control_region = part.boss_top;
  return o;
}

bool classify(const Part& part, femorph::DeformPlan& plan) {
  const femorph::RegionGraph graph = femorph::region_adjacency(part.mesh, part.regions.size());
  const femorph::Status s = femorph::classify_surface_regions(part.mesh, part.regions, graph, boss_height_options(part), plan);
  if (!s) std::fprintf(stderr, "classify_surface_regions: %s\n", s.message.c_str());
  return static_cast<bool>(s);
}

// ---- table ------------------------------------------------------------------

void print_header() {
  std::printf("%-52s %4s %10s %10s %12s  %s\n", "step", "runs", "median s", "goal s", "thesis s", "goal");
}

void print_row(const char* name, int runs, double seconds, double goal, const char* thesis) {
  std::printf("%-52s %4d %10.4f %10.4f %12s  %s\n", name, runs, seconds, goal, thesis,
              std::isnan(goal) ? "-" : (seconds <= goal ? "met" : "NOT met"));
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  int runs = 5, deform_runs = 3, param_triangles = 95000, deform_triangles = 115000;
  std::size_t inner_target = 5000;
  bool peer = true, deform_on = true, param_on = true, whole_on = true;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--runs=", 7) == 0) runs = std::max(1, std::atoi(argv[i] + 7));
    else if (std::strncmp(argv[i], "--deform-runs=", 14) == 0) deform_runs = std::max(1, std::atoi(argv[i] + 14));
    else if (std::strncmp(argv[i], "--param-triangles=", 18) == 0) param_triangles = std::atoi(argv[i] + 18);
    else if (std::strncmp(argv[i], "--deform-triangles=", 19) == 0) deform_triangles = std::atoi(argv[i] + 19);
    else if (std::strncmp(argv[i], "--inner=", 8) == 0) inner_target = static_cast<std::size_t>(std::atol(argv[i] + 8));
    else if (std::strcmp(argv[i], "--no-peer") == 0) peer = false;
    else if (std::strcmp(argv[i], "--no-deform") == 0) deform_on = false;
    else if (std::strcmp(argv[i], "--no-param") == 0) param_on = false;
    else if (std::strcmp(argv[i], "--no-whole") == 0) whole_on = false;
    else if (std::strcmp(argv[i], "--cpu") == 0) g_cpu_time = true;
    else {
      std::fprintf(stderr,
                   "usage: %s [--runs=5] [--deform-runs=3] [--param-triangles=95000] [--deform-triangles=115000] "
                   "[--inner=5000] [--no-peer] [--no-deform] [--no-param] [--no-whole] [--cpu]\n",
                   argv[0]);
      return 2;
    }
  }
  const int threads = femorph::parallel_threads();
  std::printf("FEMorph Deform benchmark: boss_block, boss height 15 -> 20 (Distance on the boss top), %d threads, "
              "medians of %d runs (deform + improve: %d)\n",
              threads, runs, deform_runs);

  // ---- parameterisation and repositioning --------------------------------
  const std::string param_path = param_on ? fine_part(param_triangles) : std::string();
  if (param_on) {
  if (param_path.empty()) return 1;
  Part part;
  if (!load_part(param_path, part)) return 1;
  femorph::DeformPlan plan;
  if (!classify(part, plan)) return 1;
  std::printf("part: %s: %zu vertices, %zu tets, %zu regions (segmented in %.2f s), boss top region %d, "
              "boss height now %.6g\n",
              param_path.c_str(), part.vertices, part.tets, part.regions.size(), part.seconds_segment, part.boss_top,
              plan.current);

  // Whole mesh.
  femorph::VertexParameterization whole;
  std::vector<double> whole_surface, whole_inner, whole_rows;
  long rss0 = peak_start();
  bool ok = true;
  const double t_whole = !whole_on ? NAN : time_median(runs, [&] {
    const auto t0 = Clock::now();
    ok = ok && femorph::parameterize_vertices(part.mesh, plan, {}, whole);
    whole_surface.push_back(whole.seconds_surface);
    whole_inner.push_back(whole.seconds_inner);
    whole_rows.push_back(seconds_since(t0) - whole.seconds_surface - whole.seconds_inner);
  });
  const long whole_peak = status_kb("VmHWM") - rss0;
  if (!ok) {
    std::fprintf(stderr, "parameterize_vertices failed on the whole mesh\n");
    return 1;
  }
  // Where its time goes: the core's timers (seconds_surface: everything up
  // to the inner factorisation, i.e. the boundary extraction, the
  // classification, all rows and the curve and surface factorisations;
  // seconds_inner: the inner factorisation) and the boundary extraction it
  // starts with, timed alone.
  femorph::SurfaceMesh boundary;
  const double t_extract = time_median(runs, [&] { femorph::extract_boundary_surface(part.mesh, boundary); });

  // Local region of about inner_target inner unknowns: bisection on the reach.
  double lo = 0, hi = plan.part_size;
  double reach = 0;
  femorph::VertexParameterization local;
  std::vector<std::uint8_t> region;
  for (int it = 0; it < 30; ++it) {
    const double mid = 0.5 * (lo + hi);
    std::vector<std::uint8_t> r = femorph::extract_deformable_region(part.mesh, plan, mid);
    femorph::VertexParameterization p;
    if (!femorph::parameterize_vertices(part.mesh, plan, r, p)) return 1;
    const std::size_t n = p.inner.unknowns.size();
    if (region.empty() || std::abs(static_cast<double>(n) - static_cast<double>(inner_target)) <
                            std::abs(static_cast<double>(local.inner.unknowns.size()) - static_cast<double>(inner_target))) {
      reach = mid;
      region = r;
      local = std::move(p);
    }
    if (n < inner_target) lo = mid;
    else hi = mid;
    if (std::abs(static_cast<double>(n) - static_cast<double>(inner_target)) <= 0.02 * static_cast<double>(inner_target))
      break;
  }
  std::size_t region_tets = 0;
  for (const auto d : region) region_tets += d != 0;
  std::vector<double> local_surface, local_inner, local_rows;
  const double t_local = time_median(runs, [&] {
    const auto t0 = Clock::now();
    ok = ok && femorph::parameterize_vertices(part.mesh, plan, region, local);
    local_surface.push_back(local.seconds_surface);
    local_inner.push_back(local.seconds_inner);
    local_rows.push_back(seconds_since(t0) - local.seconds_surface - local.seconds_inner);
  });
  const double t_region = time_median(runs, [&] { femorph::extract_deformable_region(part.mesh, plan, reach); });

  // Repositioning for new targets on the local parameterisation.
  std::vector<Vec3> points;
  const double targets[2] = {20.0, 17.5};
  int k = 0;
  femorph::SurfaceUpdate update;
  const double t_update = time_median(runs, [&] { update = femorph::update_region_surfaces(plan, part.regions, targets[k++ % 2]); });
  if (!update.error.empty()) {
    std::fprintf(stderr, "update_region_surfaces: %s\n", update.error.c_str());
    return 1;
  }
  // With the parameterisation's solve history (DeformSession's way): the
  // first target is solved, later ones are superposed where the history
  // spans them (a distance is linear in the target). Without it every
  // target is solved.
  femorph::RepositionHistory history;
  femorph::reposition_vertices(part.mesh, part.regions, local,
                               femorph::update_region_surfaces(plan, part.regions, 21.0), points, &history);
  k = 0;
  std::vector<Vec3> superposed, solved;
  double superposition_error = 0;
  const double t_reposition = time_median(runs, [&] {
    const femorph::SurfaceUpdate u = femorph::update_region_surfaces(plan, part.regions, targets[k++ % 2]);
    femorph::reposition_vertices(part.mesh, part.regions, local, u, superposed, &history);
  });
  k = 0;
  const double t_reposition_solved = time_median(runs, [&] {
    const femorph::SurfaceUpdate u = femorph::update_region_surfaces(plan, part.regions, targets[k++ % 2]);
    femorph::reposition_vertices(part.mesh, part.regions, local, u, solved);
  });
  for (const double target : targets) {
    const femorph::SurfaceUpdate u = femorph::update_region_surfaces(plan, part.regions, target);
    femorph::reposition_vertices(part.mesh, part.regions, local, u, superposed, &history);
    femorph::reposition_vertices(part.mesh, part.regions, local, u, solved);
    for (std::size_t v = 0; v < solved.size(); ++v) {
      superposition_error = std::max(superposition_error, (superposed[v] - solved[v]).norm());
    }
  }
  const double t_reposition_whole = !whole_on ? NAN : time_median(runs, [&] {
    const femorph::SurfaceUpdate u = femorph::update_region_surfaces(plan, part.regions, targets[k++ % 2]);
    femorph::reposition_vertices(part.mesh, part.regions, whole, u, points);
  });

  if (whole_on)
    std::printf("whole mesh: unknowns curve %zu, surface %zu, inner %zu; fixed/mapped the rest\n",
              whole.curves.unknowns.size(), whole.surfaces.unknowns.size(), whole.inner.unknowns.size());
  std::printf("local region: reach %.4g mm (bisection), %zu deformable tets, unknowns curve %zu, surface %zu, "
              "inner %zu\n",
              reach, region_tets, local.curves.unknowns.size(), local.surfaces.unknowns.size(),
              local.inner.unknowns.size());
  print_header();
  print_row("parameterize_vertices, whole mesh", runs, t_whole, 1.5, "15.0");
  if (whole_on)
    std::printf("  of which: up to the inner factorisation %.4f s (boundary extraction alone %.4f s), inner "
              "factorisation %.4f s, outside the core's timers %.4f s\n",
              median(whole_surface), t_extract, median(whole_inner), median(whole_rows));
  print_row("parameterize_vertices, local region", runs, t_local, 0.05, "0.10");
  std::printf("  of which: up to the inner factorisation %.4f s (boundary extraction of the whole mesh alone "
              "%.4f s), inner factorisation %.4f s, outside the core's timers %.4f s\n",
              median(local_surface), t_extract, median(local_inner), median(local_rows));
  print_row("  extract_deformable_region (not in the row above)", runs, t_region, NAN, "-");
  print_row("update_region_surfaces + reposition_vertices, local", runs, t_reposition, 0.005, "0.0074");
  std::printf("  of which update_region_surfaces %.6f s; %zu solutions stored in the history; largest "
              "vertex difference to a solve %.2e mm\n",
              t_update, history.inner.size(), superposition_error);
  print_row("  the same, every target solved (no history)", runs, t_reposition_solved, NAN, "-");
  print_row("update_region_surfaces + reposition_vertices, whole", runs, t_reposition_whole, NAN, "-");

  // The same local rows for the hole's radius 6 -> 7 (CylinderRadius): a
  // smaller feature, whose local region can be as small as the goal's ~5,000
  // inner unknowns (the boss's cannot: the boss itself has more).
  if (part.hole >= 0) {
    femorph::DeformOptions ho;
    ho.type = femorph::DeformationType::CylinderRadius;
    ho.control_region = part.hole;
    femorph::DeformPlan hole_plan;
    const femorph::Status hs = femorph::classify_surface_regions(
        part.mesh, part.regions, femorph::region_adjacency(part.mesh, part.regions.size()), ho, hole_plan);
    if (!hs) {
      std::fprintf(stderr, "classify_surface_regions (hole): %s\n", hs.message.c_str());
      return 1;
    }
    double hole_reach = 0;
    std::vector<std::uint8_t> hole_region;
    femorph::VertexParameterization hole_local;
    double hlo = 0, hhi = hole_plan.part_size;
    for (int it = 0; it < 30; ++it) {
      const double mid = 0.5 * (hlo + hhi);
      std::vector<std::uint8_t> r = femorph::extract_deformable_region(part.mesh, hole_plan, mid);
      femorph::VertexParameterization p;
      if (!femorph::parameterize_vertices(part.mesh, hole_plan, r, p)) return 1;
      const double n = static_cast<double>(p.inner.unknowns.size()), goal = static_cast<double>(inner_target);
      if (hole_region.empty() || std::abs(n - goal) < std::abs(static_cast<double>(hole_local.inner.unknowns.size()) - goal)) {
        hole_reach = mid;
        hole_region = r;
        hole_local = std::move(p);
      }
      if (n < goal) hlo = mid;
      else hhi = mid;
      if (std::abs(n - goal) <= 0.02 * goal) break;
    }
    std::size_t hole_tets = 0;
    for (const auto d : hole_region) hole_tets += d != 0;
    const double t_hole = time_median(runs, [&] {
      ok = ok && femorph::parameterize_vertices(part.mesh, hole_plan, hole_region, hole_local);
    });
    const double t_hole_region =
        time_median(runs, [&] { femorph::extract_deformable_region(part.mesh, hole_plan, hole_reach); });
    // A drag: a new target every run (6.5 .. 7.5, none repeated), after one
    // first solve at 7.5.
    const auto hole_target = [](int i) { return 6.5 + std::fmod(0.618034 * (i + 1), 1.0); };
    femorph::RepositionHistory hole_history;
    femorph::reposition_vertices(part.mesh, part.regions, hole_local,
                                 femorph::update_region_surfaces(hole_plan, part.regions, 7.5), points, &hole_history);
    k = 0;
    const int sweep = std::max(runs, 10);  // a sweep over ten values at least
    const double t_hole_reposition = time_median(sweep, [&] {
      const femorph::SurfaceUpdate u = femorph::update_region_surfaces(hole_plan, part.regions, hole_target(k++));
      femorph::reposition_vertices(part.mesh, part.regions, hole_local, u, superposed, &hole_history);
    });
    // The last target's superposed positions against a solve.
    double hole_error = 0;
    {
      const femorph::SurfaceUpdate u = femorph::update_region_surfaces(hole_plan, part.regions, hole_target(k - 1));
      femorph::reposition_vertices(part.mesh, part.regions, hole_local, u, solved);
      for (std::size_t v = 0; v < solved.size(); ++v)
        hole_error = std::max(hole_error, (superposed[v] - solved[v]).norm());
    }
    std::printf("hole radius 6 -> 7 (region %d): local region: reach %.4g mm (bisection), %zu deformable tets, "
                "unknowns curve %zu, surface %zu, inner %zu\n",
                part.hole, hole_reach, hole_tets, hole_local.curves.unknowns.size(),
                hole_local.surfaces.unknowns.size(), hole_local.inner.unknowns.size());
    print_row("parameterize_vertices, local region (hole)", runs, t_hole, 0.05, "0.10");
    print_row("  extract_deformable_region (not in the row above)", runs, t_hole_region, NAN, "-");
    print_row("update_region_surfaces + reposition_vertices (hole)", sweep, t_hole_reposition, 0.005, "0.0074");
    std::printf("  %d targets, %zu solutions stored in the history; largest vertex difference to a solve %.3g mm\n",
                k + 1, hole_history.inner.size(), hole_error);
  } else {
    std::printf("no hole region (cylinder r 6 at x 75, y 30) found: no hole rows\n");
  }
  if (whole_on)
    std::printf("memory: whole-mesh parameterisation peak %.0f bytes per tet above the resident set before it "
              "(%.1f MB for %zu tets)\n",
              1024.0 * static_cast<double>(whole_peak) / static_cast<double>(part.tets),
              static_cast<double>(whole_peak) / 1024, part.tets);

  }
  if (!deform_on) return 0;

  // ---- deform + improve against Gmsh re-meshing ---------------------------
  const std::string deform_path = fine_part(deform_triangles);
  if (deform_path.empty()) return 1;
  Part big;
  if (!load_part(deform_path, big)) return 1;
  std::printf("\ndeform + improve part: %s: %zu vertices, %zu tets, %zu regions (segmented in %.2f s)\n",
              deform_path.c_str(), big.vertices, big.tets, big.regions.size(), big.seconds_segment);
  femorph::DeformMeshOptions mo;
  mo.target = 20;
  mo.improve = true;
  std::vector<double> times, cpu_times;
  femorph::DeformReport report;
  femorph::CompactMesh result;
  long deform_peak = 0;
  for (int r = 0; r < deform_runs; ++r) {
    femorph::TetMesh mesh = big.mesh;
    femorph::DeformRegions regions = big.regions;
    femorph::DeformPlan p;
    const long before = peak_start();
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    const femorph::Status s = femorph::deform_mesh(mesh, regions, nullptr, boss_height_options(big), mo, p, report);
    times.push_back(seconds_since(t0));
    cpu_times.push_back(cpu_seconds() - c0);
    if (r == 0) deform_peak = status_kb("VmHWM") - before;
    if (!s) {
      std::fprintf(stderr, "deform_mesh failed: %s\n", s.message.c_str());
      return 1;
    }
    if (r + 1 == deform_runs) result = mesh.compact();
  }
  const long process_peak = status_kb("VmHWM");
  const double t_deform = median(times);
  std::printf("deform_mesh + improve, each run:");
  for (const double t : times) std::printf(" %.3f s", t);
  std::printf(" (process CPU:");
  for (const double t : cpu_times) std::printf(" %.3f s", t);
  std::printf(")\n");
  const femorph::ValidityReport validity = femorph::check_validity(result.points, result.tets);
  std::vector<double> stretch(result.tets.size());
  femorph::compute_tet_quality(result.points, result.tets, stretch.data(), nullptr, nullptr, nullptr, nullptr);
  std::size_t deformable_tets = 0;
  for (const auto d : report.deformable) deformable_tets += d != 0;
  const double min_q = stretch.empty() ? NAN : *std::min_element(stretch.begin(), stretch.end());
  std::printf("deform_mesh, last run: %d step(s), boss height %.6g -> %.6g (valid range [%.4g, %.4g]); %zu deformable "
              "tets, %zu inner and %zu boundary unknowns, %zu moved vertices, %zu tets inverted before improve; "
              "min stretch %.3f -> %.3f; output %zu tets, checker %s\n",
              report.steps, report.current, report.target, report.valid_min, report.valid_max, deformable_tets,
              report.inner_unknowns, report.surface_unknowns, report.moved_vertices, report.inverted_before_improve,
              report.min_stretch_before, min_q, result.tets.size(), validity.ok() ? "valid" : validity.summary().c_str());
  std::printf("  times: classify %.3f s, valid range %.3f s, parameterise %.3f s, reposition %.3f s, improve %.3f s, "
              "total %.3f s\n",
              report.seconds_classify, report.seconds_range, report.seconds_parameterize, report.seconds_reposition,
              report.seconds_improve, report.seconds_total);

  double t_gmsh = std::numeric_limits<double>::quiet_NaN();
  if (peer) {
    if (std::isnan(big.size_scale)) {
      std::printf("gmsh peer: no fine.size_scale in the part's JSON, left out\n");
    } else {
      char scale[32];
      std::snprintf(scale, sizeof scale, "%.17g", big.size_scale);
      const std::string cmd = std::string("/usr/bin/python3 ") + FEMORPH_BENCH_DIR + "/gmsh_remesh_peer.py " +
                              FEMORPH_DATA_DIR + " boss_block " + scale + " " + std::to_string(threads) +
                              " boss_height=20 2>&1";
      const std::string log = run_capture(cmd);
      t_gmsh = value_of(log, "seconds");
      if (std::isnan(t_gmsh)) std::printf("gmsh peer failed: %s\n", log.substr(0, 400).c_str());
      else
        std::printf("gmsh peer (boss_height 20, size scale %.4f, %d threads): surface %.2f s, volume %.2f s, %.0f "
                    "tets, %.0f nodes\n",
                    big.size_scale, threads, value_of(log, "surface"), value_of(log, "volume"), value_of(log, "tets"),
                    value_of(log, "nodes"));
    }
  }
  std::printf("%-52s %4s %10s %10s %12s  %s\n", "method", "runs", "median s", "tets", "thesis s", "");
  std::printf("%-52s %4d %10.3f %10zu %12s\n", "FEMorph deform_mesh + improve (boss height 20)", deform_runs, t_deform,
              big.tets, "64");
  if (!std::isnan(t_gmsh)) {
    std::printf("%-52s %4d %10.3f %10s %12s\n", "Gmsh re-meshing boss_height 20 (surface + volume)", 1, t_gmsh, "-",
                "227");
    const double ratio = t_gmsh / t_deform;
    std::printf("speed-up over Gmsh %.2fx (thesis 3.5x); goal >= 5x: %s\n", ratio, ratio >= 5 ? "met" : "NOT met");
  }
  std::printf("memory: deform_mesh peak %.0f bytes per tet above the resident set before it (%.1f MB); process peak "
              "%.0f bytes per tet (%.1f MB)\n",
              1024.0 * static_cast<double>(deform_peak) / static_cast<double>(big.tets),
              static_cast<double>(deform_peak) / 1024,
              1024.0 * static_cast<double>(process_peak) / static_cast<double>(big.tets),
              static_cast<double>(process_peak) / 1024);
  return 0;
}
