// Benchmark of FEMorph Tet To Hex (thesis 4.5): a structured hex grid of
// about 1,000,000 tets (55^3 hexes, C+ decomposed, interior nodes jittered),
// recombined; then the angle sweep of thesis Table 4.3 on a smaller grid, an
// unstructured Delaunay mesh of Gmsh, and Gmsh's own 3D recombination as the
// peer (gmsh_recombine_peer.py, each mode in its own process).
//
//   build/bin/bench_tet_to_hex [--cells=55] [--jitter=0.1] [--runs=5] [--no-gmsh]
//
// Prints medians of the runs (wall time, 2 threads unless OMP_NUM_THREADS),
// candidates and cells per type, hex volume ratio, minimum scaled Jacobian.
#include "common/parallel.h"
#include "hex/tet_to_hex.h"
#include "quality/tet_quality.h"
#include "test_meshes.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <sys/wait.h>

namespace {

using namespace femorph;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

const char* kKindNames[4] = { "tet", "pyramid", "prism", "hex" };

struct Run {
  TetToHexResult result;
  double seconds = 0, search = 0, adopt = 0;
};

Run recombine(const testing::TestMesh& m, const TetToHexParams& params, int runs) {
  std::vector<double> wall, search, adopt;
  Run best;
  for (int r = 0; r < runs; ++r) {
    TetToHexResult result;
    const auto start = std::chrono::steady_clock::now();
    const Status s = recombine_tetrahedra(m.points, m.tets, params, result);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!s.ok) {
      std::fprintf(stderr, "recombine_tetrahedra failed: %s\n", s.message.c_str());
      std::exit(1);
    }
    wall.push_back(seconds);
    search.push_back(result.stats.seconds_search);
    adopt.push_back(result.stats.seconds_adopt);
    best.result = std::move(result);
  }
  best.seconds = median(wall);
  best.search = median(search);
  best.adopt = median(adopt);
  return best;
}

double min_sj(const TetToHexResult& r, int kind) {
  double q = 2;
  for (index_t c = 0; c < r.cells.size(); ++c)
    if (static_cast<int>(r.cells.kinds[c]) == kind) q = std::min(q, r.min_scaled_jacobian[c]);
  return q > 1.5 ? 0.0 / 0.0 : q;
}

void print_result(const char* label, const Run& run, std::size_t tets) {
  const TetToHexStats& s = run.result.stats;
  std::printf("%-34s %9zu tets %7.3f s (search %.3f, adopt %.3f) %6.2f M tets/s\n", label, tets,
              run.seconds, run.search, run.adopt, tets / run.seconds / 1e6);
  std::printf("  %-8s %10s %10s %12s %10s\n", "type", "candidates", "cells", "volume ratio", "min SJ");
  for (int k = 3; k >= 0; --k)
    std::printf("  %-8s %10zu %10zu %12.4f %10.4f\n", kKindNames[k], s.candidates[k], s.cells[k],
                s.total_volume > 0 ? s.volume[k] / s.total_volume : 0.0, min_sj(run.result, k));
  std::printf("  non-conformal interfaces %zu\n", s.nonconformal_interfaces);
}

void write_binary(const std::string& path, const testing::TestMesh& m) {
  std::ofstream f(path, std::ios::binary);
  const std::int64_t header[2] = { static_cast<std::int64_t>(m.points.size()),
                                   static_cast<std::int64_t>(m.tets.size()) };
  f.write(reinterpret_cast<const char*>(header), sizeof header);
  for (const Vec3& p : m.points) f.write(reinterpret_cast<const char*>(p.data()), 3 * sizeof(double));
  f.write(reinterpret_cast<const char*>(m.tets.data()), static_cast<std::streamsize>(m.tets.size() * sizeof(Tet)));
}

bool read_binary(const std::string& path, testing::TestMesh& m) {
  std::ifstream f(path, std::ios::binary);
  std::int64_t header[2];
  if (!f.read(reinterpret_cast<char*>(header), sizeof header)) return false;
  m.points.resize(static_cast<std::size_t>(header[0]));
  m.tets.resize(static_cast<std::size_t>(header[1]));
  for (Vec3& p : m.points) f.read(reinterpret_cast<char*>(p.data()), 3 * sizeof(double));
  f.read(reinterpret_cast<char*>(m.tets.data()), static_cast<std::streamsize>(m.tets.size() * sizeof(Tet)));
  // Gmsh's tets have either orientation: make them positive.
  for (Tet& t : m.tets)
    if (tet_signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0)
      std::swap(t[2], t[3]);
  return static_cast<bool>(f);
}

/// Runs the peer script; returns its "gmsh ..." line, or what ended it.
std::string run_peer(const std::string& args) {
  const std::string cmd = "/usr/bin/python3 " FEMORPH_BENCH_DIR "/gmsh_recombine_peer.py " + args + " 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return "could not start python3";
  std::string out, line;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) {
    line = buf;
    if (line.rfind("gmsh ", 0) == 0) out = line;
  }
  const int status = pclose(p);
  if (!out.empty()) {
    if (out.back() == '\n') out.pop_back();
    return out;
  }
  // The shell reports a child killed by signal N as exit code 128 + N.
  if (WIFEXITED(status) && WEXITSTATUS(status) > 128)
    return "crashed (signal " + std::to_string(WEXITSTATUS(status) - 128) + "), no result";
  if (WIFEXITED(status)) return "exited with code " + std::to_string(WEXITSTATUS(status)) + ", no result";
  return "crashed";
}

}  // namespace

int main(int argc, char** argv) {
  int cells = 55, runs = 5;
  double jitter = 0.1;
  bool gmsh = true;
  for (int i = 1; i < argc; ++i) {
    if (!std::strncmp(argv[i], "--cells=", 8)) cells = std::atoi(argv[i] + 8);
    else if (!std::strncmp(argv[i], "--jitter=", 9)) jitter = std::atof(argv[i] + 9);
    else if (!std::strncmp(argv[i], "--runs=", 7)) runs = std::max(1, std::atoi(argv[i] + 7));
    else if (!std::strcmp(argv[i], "--no-gmsh")) gmsh = false;
    else {
      std::fprintf(stderr, "usage: %s [--cells=55] [--jitter=0.1] [--runs=5] [--no-gmsh]\n", argv[0]);
      return 2;
    }
  }
  std::printf("FEMorph Tet To Hex benchmark: %d threads, medians of %d runs\n\n", femorph::parallel_threads(), runs);

  // 1. The large grid: the goal is <= 10 s for about 1M tets.
  const testing::TestMesh big = testing::make_cube_mesh(cells, jitter, 7);
  const TetToHexParams defaults;
  const std::string label = std::to_string(cells) + "^3 hexes C+, jitter " + std::to_string(jitter).substr(0, 4);
  const Run main_run = recombine(big, defaults, runs);
  print_result(label.c_str(), main_run, big.tets.size());
  std::printf("  goal: <= 10 s for ~1M tets: %s\n\n", main_run.seconds <= 10 ? "met" : "NOT met");

  // 2. Thesis Table 4.3: hex volume ratio against delta_angle.
  const testing::TestMesh small = testing::make_cube_mesh(20, 0.2, 11);
  std::printf("Angle sweep (thesis Table 4.3), 20^3 hexes C+, jitter 0.2, %zu tets\n", small.tets.size());
  std::printf("  %10s %10s %10s %10s %10s %12s %10s\n", "quad angle", "hexes", "prisms", "pyramids", "tets",
              "hex vol %", "min SJ rec.");
  for (double angle : { 0.0, 5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 90.0 }) {
    TetToHexParams p;
    p.quad_angle_deg = angle;
    const Run r = recombine(small, p, 1);
    const TetToHexStats& s = r.result.stats;
    double q = 2;  // over the recombined cells (the tets left are the input's)
    for (index_t c = 0; c < r.result.cells.size(); ++c)
      if (r.result.cells.kinds[c] != CellKind::Tetra) q = std::min(q, r.result.min_scaled_jacobian[c]);
    std::printf("  %10.0f %10zu %10zu %10zu %10zu %12.2f %10.4f\n", angle, s.cells[3], s.cells[2], s.cells[1],
                s.cells[0], 100 * s.volume[3] / s.total_volume, q);
  }
  std::printf("\n");

  if (!gmsh) return 0;
  // 3. Gmsh: its recombination on our mesh, on its own mesh, and ours on
  // its unstructured Delaunay mesh of the same cube.
  const std::string dir = FEMORPH_BINARY_DIR "/bench-data";
  std::system(("mkdir -p " + dir).c_str());
  const std::string given = dir + "/tet_to_hex_grid.bin";
  write_binary(given, small);
  std::printf("Gmsh 3D recombination (Mesh.Recombine3DAll, level 2) as the peer\n");
  std::printf("  on our 20^3 grid (%zu tets): %s\n", small.tets.size(), run_peer("given " + given).c_str());
  std::printf("  on its own cube mesh (Algorithm3D 9, size 0.05): %s\n", run_peer("own 0.05").c_str());
  const std::string delaunay = dir + "/tet_to_hex_delaunay.bin";
  const std::string d = run_peer("delaunay 0.03 " + delaunay);
  std::printf("  Delaunay cube mesh, size 0.03: %s\n", d.c_str());
  testing::TestMesh unstructured;
  if (read_binary(delaunay, unstructured)) {
    const Run r = recombine(unstructured, defaults, runs);
    print_result("FEMorph on Gmsh's Delaunay mesh", r, unstructured.tets.size());
  }
  return 0;
}
