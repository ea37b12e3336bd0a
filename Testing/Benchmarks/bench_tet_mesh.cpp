// Benchmark of the core tet mesh: adjacency build, quality pass and random
// local operations on a jittered structured cube of about 1,000,000 tets made
// at run time, next to one plain pass over the arrays (the bound).
//
//   build/bin/bench_tet_mesh [--cells=56] [google benchmark flags]
//
// Prints Google Benchmark's table (medians of 5 repetitions) and then a
// summary with rates, the goals (docs/ARCHITECTURE.md), bytes per tet and
// the ratio of each step to the plain pass, all from the same run.
#include "common/parallel.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"
#include "test_meshes.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>
#include <string>

namespace {

using namespace femorph;

int g_cells = 56;  // 56^3 * 6 = 1,053,696 tets

const testing::TestMesh& cube() {
  static const testing::TestMesh m = testing::make_cube_mesh(g_cells, 0.1, 7);
  return m;
}

const TetMesh& built_cube() {
  static const TetMesh m = [] {
    TetMesh mesh;
    BuildOptions opt;
    opt.face_regions = cube().face_regions;
    const Status s = mesh.build(cube().points, cube().tets, opt);
    if (!s.ok) std::fprintf(stderr, "build failed: %s\n", s.message.c_str());
    return mesh;
  }();
  return m;
}

double g_bytes_per_tet = 0;

// The bound: one pass that reads every tet and the four points it uses.
void BM_PlainPass(benchmark::State& state) {
  const auto& m = cube();
  for (auto _ : state) {
    const double sum = parallel_reduce(
        static_cast<long>(m.tets.size()), 0.0,
        [&](long begin, long end, int) {
          double s = 0;
          for (long t = begin; t < end; ++t) {
            const Tet& T = m.tets[static_cast<std::size_t>(t)];
            s += (m.points[T[0]] + m.points[T[1]] + m.points[T[2]] + m.points[T[3]]).sum();
          }
          return s;
        },
        [](double a, double b) { return a + b; });
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(m.tets.size()));
}

// Full TetMesh::build: validation, exact orientation, face adjacency,
// manifold checks and vertex classification.
void BM_Build(benchmark::State& state) {
  const auto& m = cube();
  for (auto _ : state) {
    std::vector<Vec3> points = m.points;
    std::vector<Tet> tets = m.tets;
    BuildOptions opt;
    opt.face_regions = m.face_regions;
    TetMesh mesh;
    const auto start = std::chrono::steady_clock::now();
    const Status s = mesh.build(std::move(points), std::move(tets), opt);
    const auto stop = std::chrono::steady_clock::now();
    if (!s.ok) state.SkipWithError(s.message.c_str());
    state.SetIterationTime(std::chrono::duration<double>(stop - start).count());
    g_bytes_per_tet = static_cast<double>(mesh.memory_bytes()) / mesh.live_tets();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(m.tets.size()));
  state.counters["bytes/tet"] = g_bytes_per_tet;
}

void BM_QualityStretch(benchmark::State& state) {
  const auto& m = cube();
  std::vector<double> stretch(m.tets.size());
  for (auto _ : state) {
    compute_tet_quality(m.points, m.tets, stretch.data(), nullptr, nullptr, nullptr, nullptr);
    benchmark::DoNotOptimize(stretch.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(m.tets.size()));
}

void BM_QualityAll(benchmark::State& state) {
  const auto& m = cube();
  const std::size_t n = m.tets.size();
  std::vector<double> a(n), b(n), c(n), d(n), e(n);
  for (auto _ : state) {
    compute_tet_quality(m.points, m.tets, a.data(), b.data(), c.data(), d.data(), e.data());
    benchmark::DoNotOptimize(a.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n));
}

// A batch of seeded random local operations on a copy of the mesh, the way
// the algorithms apply them: a sweep over the tets, and on each a random
// operation (edge or face split, rule-based collapse, flip 2-3, 3-2 or 4-4)
// on a random edge or face of it, the tet given as the hint. Counts accepted
// operations (items) and attempts.
void BM_LocalOperations(benchmark::State& state) {
  const int kAttempts = 400000;
  int64_t accepted_total = 0, attempts_total = 0;
  for (auto _ : state) {
    TetMesh mesh = built_cube();  // copy, not timed
    std::mt19937_64 rng(99);
    const auto start = std::chrono::steady_clock::now();
    int64_t accepted = 0;
    index_t t = 0;
    for (int i = 0; i < kAttempts; ++i) {
      do t = (t + 1) % mesh.tet_slots();
      while (!mesh.tet_alive(t));
      const uint64_t r = rng();
      static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
      const index_t a = mesh.tet(t)[edges[r % 6][0]], b = mesh.tet(t)[edges[r % 6][1]];
      OpStatus s;
      switch ((r >> 8) % 6) {
        case 0: s = mesh.split_edge(a, b, nullptr, nullptr, t); break;
        case 1: s = mesh.split_face(t, static_cast<int>((r >> 16) & 3), nullptr, nullptr); break;
        case 2: s = mesh.collapse_edge_by_rules(a, b, nullptr, t); break;
        case 3: s = mesh.flip_23(t, static_cast<int>((r >> 16) & 3)); break;
        case 4: s = mesh.flip_32(a, b, t); break;
        default: s = mesh.flip_44(a, b, static_cast<int>((r >> 16) & 1), t); break;
      }
      accepted += s == OpStatus::Ok;
    }
    const auto stop = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(stop - start).count());
    accepted_total += accepted;
    attempts_total += kAttempts;
  }
  state.SetItemsProcessed(accepted_total);
  state.counters["attempts/s"] = benchmark::Counter(static_cast<double>(attempts_total), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_PlainPass)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Build)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_QualityStretch)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_QualityAll)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_LocalOperations)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1)->Repetitions(5)->ReportAggregatesOnly(true);

/// Keeps the medians for the summary table.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  std::map<std::string, double> rate;      // items/s, median of the repetitions
  std::map<std::string, double> attempts;  // attempts/s, median
  std::map<std::string, double> ms;        // wall time, median
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.aggregate_name != "median") continue;
      const std::string name = r.run_name.function_name;
      if (auto it = r.counters.find("items_per_second"); it != r.counters.end()) rate[name] = it->second;
      if (auto it = r.counters.find("attempts/s"); it != r.counters.end()) attempts[name] = it->second;
      ms[name] = r.GetAdjustedRealTime();
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], "--cells=", 8) == 0) g_cells = std::atoi(argv[i] + 8);
  benchmark::Initialize(&argc, argv);
  std::printf("FEMorph core mesh benchmark: jittered cube, %d^3 cells x 6 = %d tets, %d threads\n", g_cells,
              6 * g_cells * g_cells * g_cells, parallel_threads());
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  // Summary: medians of the repetitions, the goals, and how many
  // plain passes over the arrays each step costs (rate of the bound / rate).
  const double bound = reporter.rate["BM_PlainPass"];
  struct Row {
    const char* label;
    double median_ms;
    double rate;
    const char* unit;
    double goal;
  };
  const Row rows[] = {
      {"plain pass over the arrays (bound)", reporter.ms["BM_PlainPass"], bound, "tets/s", 0},
      {"adjacency build (TetMesh::build)", reporter.ms["BM_Build"], reporter.rate["BM_Build"], "tets/s", 2e6},
      {"quality pass: stretch", reporter.ms["BM_QualityStretch"], reporter.rate["BM_QualityStretch"], "tets/s", 20e6},
      {"quality pass: all measures", reporter.ms["BM_QualityAll"], reporter.rate["BM_QualityAll"], "tets/s", 0},
      {"local operations, accepted", reporter.ms["BM_LocalOperations"], reporter.rate["BM_LocalOperations"], "ops/s", 5e5},
      {"local operations, attempted", reporter.ms["BM_LocalOperations"], reporter.attempts["BM_LocalOperations"], "ops/s", 0},
  };
  std::printf("\n%-38s %10s %12s %-7s %10s %5s %11s\n", "step (median of 5 runs)", "time ms", "rate", "", "goal", "met",
              "bound/rate");
  for (const Row& r : rows) {
    char goal[32] = "-", met[8] = "";
    if (r.goal > 0) {
      std::snprintf(goal, sizeof goal, "%.3g", r.goal);
      std::snprintf(met, sizeof met, "%s", r.rate >= r.goal ? "yes" : "NO");
    }
    std::printf("%-38s %10.1f %12.4g %-7s %10s %5s %11.1f\n", r.label, r.median_ms, r.rate, r.unit, goal, met,
                r.rate > 0 ? bound / r.rate : 0.0);
  }
  std::printf("%-38s %10s %12.1f %-7s %10s %5s\n", "memory held by TetMesh", "", g_bytes_per_tet, "B/tet", "120",
              g_bytes_per_tet <= 120 ? "yes" : "NO");
  benchmark::Shutdown();
  return 0;
}
