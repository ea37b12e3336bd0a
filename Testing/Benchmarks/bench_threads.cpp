// Benchmark of FEMorph's parallel loops on a busy machine: each case with the
// default thread count and with one thread, on an idle machine and with one
// core kept busy by a spinning process this program starts and stops itself.
// The project's rule: with a busy core no case may be more than 10% slower
// than its one-thread run; idle, the default count keeps its parallel speed.
//
//   build/bin/bench_threads [--runs=5] [--bcc=16] [--cells=40] [--deform-cells=16] [--adapt-steps=4] [--only=TEXT]
//
// Cases, one per filter's core: Improve (phased_odt on a BCC box stretched x3
// in z, with the box's own density as target), Mesh Quality (the mesh build
// with a validity check and a quality pass, jittered cube), Segment and Tet
// To Hex (shared/realparts' fandisk), Deform (a face of a jittered cube moved,
// with Improve) and Adapt (steps of a block rotating in a box). Runs are interleaved (idle 1, idle default,
// busy 1, busy default) so that other load on the machine touches all four;
// the table gives medians and checks that the output does not depend on the
// thread count.
#include "adapt/adapt.h"
#include "common/parallel.h"
#include "deform/deform.h"
#include "hex/tet_to_hex.h"
#include "improve/boundary_geometry.h"
#include "improve/mesh_density.h"
#include "improve/phased_odt.h"
#include "io/read_medit_mesh.h"
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "segment/segmentation.h"
#include "test_adapt_meshes.h"
#include "test_meshes.h"
#include "test_surfaces.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace femorph;
using Clock = std::chrono::steady_clock;

int default_threads() { return parallel_threads(); }
void set_threads(int n) { set_parallel_threads(n); }

/// A child process spinning on one core until stop() (or this program's end).
class Spinner {
 public:
  void start() {
    pid_ = fork();
    if (pid_ == 0) {
      volatile unsigned long x = 0;
      for (;;) x = x + 1;
    }
    if (pid_ < 0) std::perror("fork");
  }
  void stop() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  ~Spinner() { stop(); }

 private:
  pid_t pid_ = -1;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// One case: run() returns a digest of its output (equal digests: equal output).
struct Case {
  std::string name;
  std::function<std::uint64_t()> run;
};

std::uint64_t digest(const std::vector<Vec3>& points, const std::vector<Tet>& tets) {
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&](const void* data, std::size_t bytes) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(points.data(), points.size() * sizeof(Vec3));
  mix(tets.data(), tets.size() * sizeof(Tet));
  return h;
}

Case improve_case(int n) {
  const testing::TestMesh ref = testing::make_bcc_box_mesh(n, 2);
  const double factor = 3.0, top = 1.0 + factor;
  testing::TestMesh deformed = ref;
  for (Vec3& p : deformed.points)
    p.z() = p.z() <= 0.5 ? p.z() : (p.z() >= 1.5 ? p.z() + (factor - 1) : 0.5 + factor * (p.z() - 0.5));
  const std::vector<double> rho = vertex_density(ref.points, ref.tets);
  auto grid = std::make_shared<DensityGrid>();
  grid->build(deformed.points, ref.tets, rho, 0);
  BoundaryGeometry geometry;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      geometry.regions.push_back(test_surfaces::plane(side * (axis == 2 ? top : 1.0) * Vec3::Unit(axis),
                                                               Vec3::Unit(axis)));
  char name[96];
  std::snprintf(name, sizeof name, "Improve: phased_odt, BCC box x3 (%zu tets)", ref.tets.size());
  return {name, [deformed, grid, geometry]() {
            TetMesh mesh;
            BuildOptions options;
            options.face_regions = deformed.face_regions;
            mesh.build(deformed.points, deformed.tets, options);
            PhasedOdtTarget target;
            target.density = grid.get();
            phased_odt(mesh, geometry, target);
            const CompactMesh out = mesh.compact();
            return digest(out.points, out.tets);
          }};
}

Case mesh_case(int cells) {
  const testing::TestMesh cube = testing::make_cube_mesh(cells, 0.1, 7);
  char name[96];
  std::snprintf(name, sizeof name, "TetMesh build + validity + quality (%zu tets)", cube.tets.size());
  return {name, [cube]() {
            const ValidityReport report = check_validity(cube.points, cube.tets);
            TetMesh mesh;
            BuildOptions options;
            options.face_regions = cube.face_regions;
            mesh.build(cube.points, cube.tets, options);
            const CompactMesh out = mesh.compact();
            std::vector<double> q(out.tets.size());
            compute_tet_quality(out.points, out.tets, q.data(), nullptr, nullptr, nullptr, nullptr);
            std::uint64_t h = digest(out.points, out.tets) ^ static_cast<std::uint64_t>(report.ok());
            for (const double x : q) h = (h ^ static_cast<std::uint64_t>(x * 1e15)) * 1099511628211ull;
            return h;
          }};
}


/// A Medit mesh of shared/realparts; empty (the case is skipped) when absent.
MeditMesh real_part(const char* name) {
  MeditMesh medit;
  const std::string path = std::string(FEMORPH_REALPARTS_DIR) + "/" + name;
  if (!read_medit_mesh(path, medit)) {
    std::printf("(%s not readable: its cases are skipped)\n", path.c_str());
    medit = {};
  }
  for (Tet& t : medit.tets)  // positively oriented, as recombine_tetrahedra wants
    if (tet_signed_volume(medit.points[t[0]], medit.points[t[1]], medit.points[t[2]], medit.points[t[3]]) < 0)
      std::swap(t[2], t[3]);
  return medit;
}

Case segment_case(const MeditMesh& part) {
  char name[96];
  std::snprintf(name, sizeof name, "Segment: segment_boundary, fandisk (%zu tets)", part.tets.size());
  return {name, [part]() {
            TetMesh mesh;
            mesh.build(part.points, part.tets);
            SurfaceMesh surface;
            Segmentation seg;
            segment_boundary(mesh, SegmentationParams{}, surface, seg);
            std::uint64_t h = seg.regions.size();
            for (const index_t r : seg.triangle_region) h = (h ^ static_cast<std::uint64_t>(r)) * 1099511628211ull;
            return h;
          }};
}

Case tet_to_hex_case(const MeditMesh& part) {
  char name[96];
  std::snprintf(name, sizeof name, "Tet To Hex: recombine_tetrahedra, fandisk (%zu tets)", part.tets.size());
  return {name, [part]() {
            TetToHexResult result;
            recombine_tetrahedra(part.points, part.tets, TetToHexParams{}, result);
            std::uint64_t h = result.cells.size();
            for (const index_t t : result.source_tets) h = (h ^ static_cast<std::uint64_t>(t)) * 1099511628211ull;
            return h;
          }};
}

Case deform_case(int cells) {
  const testing::TestMesh cube = testing::make_cube_mesh(cells, 0.1, 11);
  char name[96];
  std::snprintf(name, sizeof name, "Deform: deform_mesh + Improve, cube face 1 -> 1.4 (%zu tets)", cube.tets.size());
  return {name, [cube]() {
            TetMesh mesh;
            BuildOptions options;
            options.face_regions = cube.face_regions;
            mesh.build(cube.points, cube.tets, options);
            mesh.classify_vertices();
            DeformRegions regions;
            for (int r = 0; r < 6; ++r) {
              SurfacePrimitive s;
              s.type = SurfaceType::Plane;
              s.axis = Vec3::Zero();
              s.axis[r / 2] = r % 2 ? 1.0 : -1.0;
              s.point = Vec3::Zero();
              s.point[r / 2] = r % 2 ? 1.0 : 0.0;
              regions.surfaces.push_back(s);
              regions.convexity.push_back(Convexity::NotApplicable);
            }
            DeformOptions o;
            o.control_region = 1;
            DeformMeshOptions mo;
            mo.target = 1.4;
            DeformPlan plan;
            DeformReport report;
            deform_mesh(mesh, regions, nullptr, o, mo, plan, report);
            const CompactMesh out = mesh.compact();
            return digest(out.points, out.tets);
          }};
}

Case adapt_case(int steps) {
  const testing::MaterialMesh in = testing::make_block_in_box({10, 10, 10}, {3, 2, 1}, 1.0, 0.15, 3);
  RigidMotion motion;
  motion.rotation_center = 0.5 * (in.object_lo + in.object_hi);
  motion.rotation_axis = Vec3(0, 0, 1);
  motion.rotation_degrees_per_step = 5;
  char name[96];
  std::snprintf(name, sizeof name, "Adapt: %d steps of 5 deg, block in box (%zu tets)", steps, in.tets.size());
  return {name, [in, motion, steps]() {
            AdaptSession session;
            std::uint64_t h = session.init(in.points, in.tets, in.material, motion, AdaptOptions{}).ok;
            for (int n = 0; n < steps; ++n) h = h * 3 + session.advance().ok;
            const AdaptOutput out = session.output();
            return h ^ digest(out.points, out.tets);
          }};
}
}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::string only;  // run only the cases whose name contains it
  int runs = 5, bcc = 16, cells = 40, deform_cells = 16, adapt_steps = 4;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--runs=", 7) == 0) runs = std::max(1, std::atoi(argv[i] + 7));
    else if (std::strncmp(argv[i], "--bcc=", 6) == 0) bcc = std::max(2, std::atoi(argv[i] + 6));
    else if (std::strncmp(argv[i], "--cells=", 8) == 0) cells = std::max(2, std::atoi(argv[i] + 8));
    else if (std::strncmp(argv[i], "--deform-cells=", 15) == 0) deform_cells = std::max(3, std::atoi(argv[i] + 15));
    else if (std::strncmp(argv[i], "--only=", 7) == 0) only = argv[i] + 7;
    else if (std::strncmp(argv[i], "--adapt-steps=", 14) == 0) adapt_steps = std::max(1, std::atoi(argv[i] + 14));
    else {
      std::fprintf(stderr, "usage: %s [--runs=5] [--bcc=16] [--cells=40] [--deform-cells=16] [--adapt-steps=4] "
                           "[--only=TEXT]\n",
                   argv[0]);
      return 2;
    }
  }
  const int threads = default_threads();
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  std::printf("%ld cores, default thread count %d; busy: one spinning child process; medians of %d runs\n", cores,
              threads, runs);
  std::vector<Case> cases = {improve_case(bcc), mesh_case(cells), deform_case(deform_cells), adapt_case(adapt_steps)};
  const MeditMesh fandisk = real_part("fandisk_tet.mesh");
  if (!fandisk.tets.empty()) {
    cases.push_back(segment_case(fandisk));
    cases.push_back(tet_to_hex_case(fandisk));
  }
  std::printf("\n| case | idle, 1 thread | idle, %d threads | busy core, 1 thread | busy core, %d threads "
              "| busy %d / busy 1 | idle %d / idle 1 | same output |\n|---|---|---|---|---|---|---|---|\n",
              threads, threads, threads, threads);
  for (const Case& c : cases) {
    if (c.name.find(only) == std::string::npos) continue;
    std::vector<double> t[4];
    std::uint64_t first = 0;
    bool same = true, have = false;
    for (int r = 0; r < runs; ++r) {
      for (int k = 0; k < 4; ++k) {
        const bool busy = k >= 2;
        set_threads(k % 2 ? threads : 1);
        Spinner spinner;
        if (busy) {
          spinner.start();
          usleep(20000);  // let it reach its core
        }
        const auto t0 = Clock::now();
        const std::uint64_t h = c.run();
        t[k].push_back(std::chrono::duration<double>(Clock::now() - t0).count());
        spinner.stop();
        if (!have) first = h, have = true;
        same = same && h == first;
      }
    }
    set_threads(threads);
    const double m[4] = {median(t[0]), median(t[1]), median(t[2]), median(t[3])};
    std::printf("| %s | %.3f s | %.3f s | %.3f s | %.3f s | %.2f | %.2f | %s |\n", c.name.c_str(), m[0], m[1], m[2],
                m[3], m[3] / m[2], m[1] / m[0], same ? "yes" : "NO");
  }
  return 0;
}
