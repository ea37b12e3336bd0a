// FEMorph Adapt's core (thesis chapter 3) on the case of thesis 3.7.2: a
// 3x5x1-cube object in a 20x20x50 grid of cubes (12 tets each, jittered),
// moving 0.1 along z and turning 1 degree about x through its centre per
// step; and a long rotation in place (900 steps of 1 degree).
//
//   bench_adapt [--cells=20,20,50] [--object=3,5,1] [--steps=360] [--runs=1]
//               [--rotation-steps=900] [--no-rotation] [--no-peer]
//               [--peer-steps=10] [--every=36]
//
// Prints every --every steps a row (step, vertices, tets, min and mean
// stretch, region tets, sub-steps, ms), then per case: the median s/step, the
// minimum stretch over all steps against the input's, the vertex drift; and
// the peer measured in the same command: Gmsh re-meshing the exact geometry
// of sampled steps (adapt_gmsh_peer.py), its s/step and the fraction of
// vertices that keep their position (Adapt keeps every vertex outside the
// deformed regions).
#include "adapt/adapt.h"
#include "quality/tet_quality.h"
#include "test_adapt_meshes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
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

}  // namespace

int main(int argc, char** argv) {
  std::array<int, 3> cells{{20, 20, 50}}, object{{3, 5, 1}};
  int steps = 360, rotation_steps = 900, every = 36, peer_steps = 10;
  bool rotation = true, peer = true;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--cells=", 8) == 0) cells = parse3(argv[i] + 8);
    else if (std::strncmp(argv[i], "--object=", 9) == 0) object = parse3(argv[i] + 9);
    else if (std::strncmp(argv[i], "--steps=", 8) == 0) steps = std::atoi(argv[i] + 8);
    else if (std::strncmp(argv[i], "--rotation-steps=", 17) == 0) rotation_steps = std::atoi(argv[i] + 17);
    else if (std::strncmp(argv[i], "--every=", 8) == 0) every = std::max(1, std::atoi(argv[i] + 8));
    else if (std::strncmp(argv[i], "--peer-steps=", 13) == 0) peer_steps = std::atoi(argv[i] + 13);
    else if (std::strcmp(argv[i], "--no-rotation") == 0) rotation = false;
    else if (std::strcmp(argv[i], "--no-peer") == 0) peer = false;
    else {
      std::fprintf(stderr,
                   "usage: %s [--cells=20,20,50] [--object=3,5,1] [--steps=360] [--rotation-steps=900] "
                   "[--every=36] [--peer-steps=10] [--no-rotation] [--no-peer]\n",
                   argv[0]);
      return 2;
    }
  }
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
  const CaseResult a = run_case("3.7.2 translate + rotate", in, motion, steps, every);
  CaseResult b;
  if (rotation) {
    RigidMotion spin;
    spin.rotation_axis = Vec3(1, 0, 0);
    spin.rotation_center = motion.rotation_center;
    spin.rotation_degrees_per_step = 1;
    b = run_case("rotation in place", in, spin, rotation_steps, std::max(every, rotation_steps / 10));
  }
  double peer_step = NAN;
  if (peer) {
    const std::string script = std::string(FEMORPH_BENCH_DIR) + "/adapt_gmsh_peer.py";
    if (!std::filesystem::exists(script)) {
      std::printf("\ngmsh peer: %s not found, left out\n", script.c_str());
    } else {
      char cmd[1024];
      std::snprintf(cmd, sizeof cmd, "/usr/bin/python3 %s --cells %d %d %d --object %d %d %d --steps %d --stride %d 2>&1",
                    script.c_str(), cells[0], cells[1], cells[2], object[0], object[1], object[2], peer_steps,
                    std::max(1, steps / std::max(1, peer_steps)));
      std::printf("\ngmsh peer: %s\n", cmd);
      std::fflush(stdout);
      FILE* p = popen(cmd, "r");
      char line[4096];
      while (p && std::fgets(line, sizeof line, p)) {
        std::fputs(line, stdout);
        double x;
        if (std::sscanf(line, "median s/step %lf", &x) == 1) peer_step = x;
      }
      if (p) pclose(p);
    }
  }
  std::printf("\nsummary (goals: min stretch >= input's, drift <= 3%% (rotation: 5%%), <= 20 ms/step)\n");
  std::printf("%-18s %10s %12s %10s %9s %14s\n", "case", "ms/step", "min stretch", "input min", "drift %",
              "kept/step %");
  std::printf("%-18s %10.2f %12.4f %10.4f %9.2f %14.1f\n", "translate+rotate", 1e3 * a.median_step, a.min_stretch,
              a.input_min, 100 * a.drift, 100 * a.kept_step);
  if (rotation)
    std::printf("%-18s %10.2f %12.4f %10.4f %9.2f %14.1f\n", "rotation", 1e3 * b.median_step, b.min_stretch,
                b.input_min, 100 * b.drift, 100 * b.kept_step);
  if (!std::isnan(peer_step))
    std::printf("%-18s %10.2f %12s %10s %9s %14s   Adapt %.0fx faster per step\n", "gmsh re-mesh", 1e3 * peer_step,
                "(below)", "", "", "(below)", peer_step / a.median_step);
  return a.error.empty() && b.error.empty() ? 0 : 1;
}
