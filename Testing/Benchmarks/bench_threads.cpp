// Benchmark of FEMorph's parallel loops on a busy machine: each case with the
// default thread count and with one thread, on an idle machine and with one
// core kept busy by a spinning process this program starts and stops itself.
// The project's rule: with a busy core no case may be more than 10% slower
// than its one-thread run; idle, the default count keeps its parallel speed.
//
//   build/bin/bench_threads [--runs=5] [--bcc=16] [--cells=40]
//
// Cases: Improve's core (phased_odt on a BCC box stretched x3 in z, with the
// box's own density as target) and the mesh build with a validity check and
// a quality pass (jittered cube). Runs are interleaved (idle 1, idle default,
// busy 1, busy default) so that other load on the machine touches all four;
// the table gives medians and checks that the output does not depend on the
// thread count.
#include "common/parallel.h"
#include "improve/boundary_geometry.h"
#include "improve/mesh_density.h"
#include "improve/phased_odt.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
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

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  int runs = 5, bcc = 16, cells = 40;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--runs=", 7) == 0) runs = std::max(1, std::atoi(argv[i] + 7));
    else if (std::strncmp(argv[i], "--bcc=", 6) == 0) bcc = std::max(2, std::atoi(argv[i] + 6));
    else if (std::strncmp(argv[i], "--cells=", 8) == 0) cells = std::max(2, std::atoi(argv[i] + 8));
    else {
      std::fprintf(stderr, "usage: %s [--runs=5] [--bcc=16] [--cells=40]\n", argv[0]);
      return 2;
    }
  }
  const int threads = default_threads();
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  std::printf("%ld cores, default thread count %d; busy: one spinning child process; medians of %d runs\n", cores,
              threads, runs);
  const std::vector<Case> cases = {improve_case(bcc), mesh_case(cells)};
  std::printf("\n| case | idle, 1 thread | idle, %d threads | busy core, 1 thread | busy core, %d threads "
              "| busy %d / busy 1 | idle %d / idle 1 | same output |\n|---|---|---|---|---|---|---|---|\n",
              threads, threads, threads, threads);
  for (const Case& c : cases) {
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
