// Benchmark of FEMorph Improve (thesis 2.6, issue 5): case (b), the boss of
// boss_block at about 500,000 tets stretched x1.6 (and x3) along its axis as a
// boss-height change does (thesis Fig. 2.53), improved by vtkFEMorphImprove
// with the part before the stretch as its Reference; in the same command the
// peers on the same stretched mesh: TetGen's optimizer (`tetgen -r` with -O,
// Debian's tetgen 1.5) and Gmsh's (gmsh.model.mesh.optimize default and
// "Relocate3D", gmsh_optimize_peer.py with Debian's python3-gmsh 4.8).
//
//   build/bin/bench_improve [--runs=3] [--factors=1.6,3] [--part=PATH] [--no-peers]
//
// Every output is measured by the same code (Core/quality): tets, minimum and
// mean stretch (Eq. 1.1), minimum dihedral angle, inverted tets, the
// independent validity checker, and how many of the input's boundary points
// are no longer where they were (FEMorph moves them along the fitted
// surfaces on purpose; TetGen -r and Gmsh keep or move them as they do).
// FEMorph's time is the median of --runs runs of the filter (the
// segmentation of the stretched part, which FEMorph Deform would hand over,
// is timed on its own); the peers run once each (they are slow) and their
// own optimizer time is what the ratio uses (Gmsh: the optimize call only;
// TetGen: the whole process, reading and writing included, also printed).
#include "vtkFEMorphImprove.h"
#include "vtkFEMorphSegment.h"

#include "quality/check_validity.h"
#include "quality/tet_quality.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkDataArray.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

using femorph::Tet;
using femorph::Vec3;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

struct Mesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
};

Mesh to_mesh(vtkUnstructuredGrid* grid) {
  Mesh m;
  m.points.resize(static_cast<std::size_t>(grid->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) grid->GetPoint(i, m.points[static_cast<std::size_t>(i)].data());
  m.tets.resize(static_cast<std::size_t>(grid->GetNumberOfCells()));
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    vtkIdType n = 0;
    const vtkIdType* p = nullptr;
    grid->GetCellPoints(c, n, p);
    for (int k = 0; k < 4; ++k) m.tets[static_cast<std::size_t>(c)][k] = static_cast<femorph::index_t>(p[k]);
  }
  return m;
}

vtkSmartPointer<vtkUnstructuredGrid> to_grid(const Mesh& m) {
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(m.points.size()));
  for (std::size_t i = 0; i < m.points.size(); ++i) points->SetPoint(static_cast<vtkIdType>(i), m.points[i].data());
  grid->SetPoints(points);
  vtkNew<vtkCellArray> cells;
  cells->AllocateExact(static_cast<vtkIdType>(m.tets.size()), 4 * static_cast<vtkIdType>(m.tets.size()));
  for (const Tet& t : m.tets) {
    const vtkIdType ids[4] = {t[0], t[1], t[2], t[3]};
    cells->InsertNextCell(4, ids);
  }
  grid->SetCells(VTK_TETRA, cells);
  return grid;
}

/// Boundary faces (each once, oriented outward for positive tets).
std::vector<std::array<femorph::index_t, 3>> boundary_faces(const Mesh& m) {
  std::map<std::array<femorph::index_t, 3>, std::pair<int, std::array<femorph::index_t, 3>>> faces;
  static const int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (const Tet& t : m.tets)
    for (const auto& f : kFace) {
      std::array<femorph::index_t, 3> oriented = {t[f[0]], t[f[1]], t[f[2]]};
      std::array<femorph::index_t, 3> key = oriented;
      std::sort(key.begin(), key.end());
      auto& e = faces[key];
      ++e.first;
      e.second = oriented;
    }
  std::vector<std::array<femorph::index_t, 3>> out;
  for (const auto& f : faces)
    if (f.second.first == 1) out.push_back(f.second.second);
  return out;
}

/// The input's boundary points, found again within 1e-9 of the part's size
/// (the peers write coordinates with fewer digits).
class BoundaryPoints {
 public:
  void build(const Mesh& m, const std::vector<std::array<femorph::index_t, 3>>& faces) {
    Vec3 lo = m.points[0], hi = lo;
    for (const Vec3& p : m.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    tolerance_ = 1e-9 * (hi - lo).norm();
    cell_ = 1e3 * tolerance_;
    for (const auto& f : faces)
      for (const auto v : f) cells_[key(m.points[v])].push_back(m.points[v]);
  }
  bool contains(const Vec3& p) const {
    const auto k = key(p);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == cells_.end()) continue;
          for (const Vec3& q : it->second)
            if ((q - p).norm() <= tolerance_) return true;
        }
    return false;
  }

 private:
  std::array<long, 3> key(const Vec3& p) const {
    return {std::lround(p.x() / cell_), std::lround(p.y() / cell_), std::lround(p.z() / cell_)};
  }
  double tolerance_ = 0, cell_ = 1;
  std::map<std::array<long, 3>, std::vector<Vec3>> cells_;
};

struct Measures {
  std::size_t tets = 0, inverted = 0, boundary_moved = 0, boundary_points = 0;
  double min_stretch = 0, mean_stretch = 0, min_dihedral = 0;
  bool valid = false;
};

Measures measure(const Mesh& m, const BoundaryPoints& input_boundary) {
  Measures r;
  r.tets = m.tets.size();
  std::vector<double> stretch(m.tets.size()), dihedral(m.tets.size()), volume(m.tets.size());
  femorph::compute_tet_quality(m.points, m.tets, stretch.data(), nullptr, dihedral.data(), nullptr, volume.data());
  r.min_stretch = *std::min_element(stretch.begin(), stretch.end());
  double sum = 0;
  for (const double s : stretch) sum += s;
  r.mean_stretch = sum / static_cast<double>(stretch.size());
  r.min_dihedral = *std::min_element(dihedral.begin(), dihedral.end()) * 180 / femorph::kPi;
  for (const double v : volume) r.inverted += v <= 0;
  r.valid = femorph::check_validity(m.points, m.tets).ok();
  // Boundary points of the output that are not input boundary points.
  std::set<femorph::index_t> bp;
  for (const auto& f : boundary_faces(m)) bp.insert(f.begin(), f.end());
  r.boundary_points = bp.size();
  for (const femorph::index_t v : bp) r.boundary_moved += !input_boundary.contains(m.points[v]);
  return r;
}

void print_row(const char* name, double seconds, const Measures& q, double femorph_seconds) {
  std::printf("%-28s %9.2f %9zu %8.3f %8.3f %8.2f %8zu %6s %9zu/%-8zu", name, seconds, q.tets, q.min_stretch,
              q.mean_stretch, q.min_dihedral, q.inverted, q.valid ? "yes" : "NO", q.boundary_moved,
              q.boundary_points);
  if (femorph_seconds > 0 && seconds > 0) std::printf(" %7.1fx", seconds / femorph_seconds);
  std::printf("\n");
}

// ---- peers ------------------------------------------------------------------

std::string run_capture(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  pclose(p);
  return out;
}

void write_tetgen(const Mesh& m, const std::string& stem) {
  std::ofstream node(stem + ".node"), ele(stem + ".ele");
  node.precision(17);
  node << m.points.size() << " 3 0 0\n";
  for (std::size_t i = 0; i < m.points.size(); ++i)
    node << i << " " << m.points[i].x() << " " << m.points[i].y() << " " << m.points[i].z() << "\n";
  ele << m.tets.size() << " 4 0\n";
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    ele << t << " " << m.tets[t][0] << " " << m.tets[t][1] << " " << m.tets[t][2] << " " << m.tets[t][3] << "\n";
}

bool read_tetgen(const std::string& stem, Mesh& m) {
  std::ifstream node(stem + ".node"), ele(stem + ".ele");
  if (!node || !ele) return false;
  std::size_t n = 0;
  int dim = 0, attrs = 0, marker = 0;
  node >> n >> dim >> attrs >> marker;
  m.points.assign(n, Vec3::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    long id;
    node >> id >> m.points[i].x() >> m.points[i].y() >> m.points[i].z();
    for (int a = 0; a < attrs + marker; ++a) {
      double skip;
      node >> skip;
    }
  }
  std::size_t nt = 0;
  int per = 0, tattrs = 0;
  ele >> nt >> per >> tattrs;
  m.tets.assign(nt, Tet{});
  for (std::size_t t = 0; t < nt; ++t) {
    long id;
    ele >> id;
    for (int k = 0; k < per; ++k) {
      long v;
      ele >> v;
      if (k < 4) m.tets[t][k] = static_cast<femorph::index_t>(v);
    }
    for (int a = 0; a < tattrs; ++a) {
      double skip;
      ele >> skip;
    }
  }
  return static_cast<bool>(ele);
}

void write_msh2(const Mesh& m, const std::string& path) {
  std::ofstream f(path);
  f.precision(17);
  f << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m.points.size() << "\n";
  for (std::size_t i = 0; i < m.points.size(); ++i)
    f << i + 1 << " " << m.points[i].x() << " " << m.points[i].y() << " " << m.points[i].z() << "\n";
  const auto faces = boundary_faces(m);
  f << "$EndNodes\n$Elements\n" << faces.size() + m.tets.size() << "\n";
  std::size_t id = 1;
  for (const auto& t : faces) f << id++ << " 2 2 1 1 " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  for (const Tet& t : m.tets)
    f << id++ << " 4 2 2 1 " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << " " << t[3] + 1 << "\n";
  f << "$EndElements\n";
}

bool read_msh2(const std::string& path, Mesh& m) {
  std::ifstream f(path);
  std::string line;
  std::map<long, femorph::index_t> ids;
  m = Mesh();
  while (std::getline(f, line)) {
    if (line == "$Nodes") {
      std::size_t n;
      f >> n;
      for (std::size_t i = 0; i < n; ++i) {
        long id;
        Vec3 p;
        f >> id >> p.x() >> p.y() >> p.z();
        ids[id] = static_cast<femorph::index_t>(m.points.size());
        m.points.push_back(p);
      }
    } else if (line == "$Elements") {
      std::size_t n;
      f >> n;
      std::getline(f, line);
      for (std::size_t i = 0; i < n; ++i) {
        std::getline(f, line);
        std::istringstream s(line);
        long id, type, ntags;
        s >> id >> type >> ntags;
        for (long k = 0; k < ntags; ++k) {
          long skip;
          s >> skip;
        }
        if (type != 4) continue;
        Tet t;
        for (int k = 0; k < 4; ++k) {
          long v;
          s >> v;
          t[k] = ids.at(v);
        }
        m.tets.push_back(t);
      }
    }
  }
  // Points no tet uses (Gmsh keeps them) would count as unused: drop them.
  std::vector<femorph::index_t> map(m.points.size(), -1);
  Mesh out;
  for (Tet& t : m.tets)
    for (auto& v : t) {
      if (map[v] < 0) {
        map[v] = static_cast<femorph::index_t>(out.points.size());
        out.points.push_back(m.points[v]);
      }
      v = map[v];
    }
  out.tets = std::move(m.tets);
  m = std::move(out);
  return !m.tets.empty();
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3;
  bool peers = true;
  std::vector<double> factors = {1.6, 3.0};
  std::string part;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--runs=", 7) == 0) runs = std::max(1, std::atoi(argv[i] + 7));
    else if (std::strcmp(argv[i], "--no-peers") == 0) peers = false;
    else if (std::strncmp(argv[i], "--part=", 7) == 0) part = argv[i] + 7;
    else if (std::strncmp(argv[i], "--factors=", 10) == 0) {
      factors.clear();
      std::stringstream s(argv[i] + 10);
      std::string item;
      while (std::getline(s, item, ',')) factors.push_back(std::atof(item.c_str()));
    } else {
      std::fprintf(stderr, "usage: %s [--runs=3] [--factors=1.6,3] [--part=PATH] [--no-peers]\n", argv[0]);
      return 2;
    }
  }
  const std::string dir = std::string(FEMORPH_BINARY_DIR) + "/bench-data/improve";
  if (part.empty()) {
    part = dir + "/boss_block_fine.vtu";
    if (!std::filesystem::exists(part)) {
      std::printf("making boss_block at about 500,000 tets with Gmsh into %s ...\n", dir.c_str());
      std::fflush(stdout);
      std::filesystem::create_directories(dir);
      const std::string cmd = std::string("/usr/bin/python3 ") + FEMORPH_DATA_DIR +
                              "/generate_parts.py --fine boss_block --target-boundary-triangles 95000 --out-dir " +
                              dir + " > " + dir + "/generate.log 2>&1";
      if (std::system(cmd.c_str()) != 0 || !std::filesystem::exists(part)) {
        std::fprintf(stderr, "could not make the part (see %s/generate.log)\n", dir.c_str());
        return 1;
      }
    }
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(part.c_str());
  reader->Update();
  vtkSmartPointer<vtkUnstructuredGrid> original = reader->GetOutput();
  const Mesh undeformed = to_mesh(original);
  // The reference, segmented once (its fits give the acceptable geometric error).
  vtkNew<vtkFEMorphSegment> reference_segment;
  reference_segment->SetInputData(original);
  reference_segment->Update();
  vtkSmartPointer<vtkUnstructuredGrid> reference = reference_segment->GetMeshOutput();

  std::printf("FEMorph Improve benchmark: %d threads, %s (%zu tets), FEMorph medians of %d runs, peers once\n",
              omp_get_max_threads(), part.c_str(), undeformed.tets.size(), runs);
  BoundaryPoints own;
  own.build(undeformed, boundary_faces(undeformed));
  const Measures und = measure(undeformed, own);
  std::printf("undeformed: min stretch %.3f, mean %.3f, min dihedral %.2f deg\n", und.min_stretch, und.mean_stretch,
              und.min_dihedral);

  for (const double factor : factors) {
    // Case (b): the boss (z from the block's top, 20, to its top, 35) x factor.
    Mesh deformed = undeformed;
    for (Vec3& p : deformed.points) {
      const double z = p.z();
      p.z() = z <= 20 ? z : (z >= 35 ? z + (factor - 1) * 15 : 20 + factor * (z - 20));
    }
    BoundaryPoints boundary;
    boundary.build(deformed, boundary_faces(deformed));
    const Measures in = measure(deformed, boundary);
    std::printf("\ncase (b), boss height x%.1f: %zu tets, stretch min %.3f mean %.3f, min dihedral %.2f deg\n", factor,
                in.tets, in.min_stretch, in.mean_stretch, in.min_dihedral);
    auto deformed_grid = to_grid(deformed);

    std::vector<double> seg_times, times;
    vtkSmartPointer<vtkUnstructuredGrid> segmented, improved;
    for (int r = 0; r < runs; ++r) {
      vtkNew<vtkFEMorphSegment> segment;
      segment->SetInputData(deformed_grid);
      auto t0 = Clock::now();
      segment->Update();
      seg_times.push_back(seconds_since(t0));
      segmented = segment->GetMeshOutput();
      vtkNew<vtkFEMorphImprove> improve;
      improve->SetInputData(segmented);
      improve->SetReferenceData(reference);
      t0 = Clock::now();
      improve->Update();
      times.push_back(seconds_since(t0));
      improved = improve->GetOutput();
    }
    const double femorph_s = median(times);
    const Measures fm = measure(to_mesh(improved), boundary);
    vtkDataArray* density = improved->GetFieldData()->GetArray("ImproveDensityError");
    std::printf("segmentation of the stretched part (FEMorph Segment): %.2f s; density error (Eq. 2.35) %.3f -> %.3f\n",
                median(seg_times), density ? density->GetComponent(0, 0) : NAN,
                density ? density->GetComponent(0, 1) : NAN);
    std::printf("%-28s %9s %9s %8s %8s %8s %8s %6s %18s %8s\n", "method", "time s", "tets", "min Q", "mean Q",
                "min dih", "inverted", "valid", "bnd pts off input", "peer/FM");
    print_row("FEMorph Improve", femorph_s, fm, 0);
    if (!peers) continue;

    // TetGen: reconstruct the mesh (-r) and optimise it (-O level/ops), then
    // the same with quality refinement (-q, adds points; -Y keeps the boundary).
    const std::string stem = dir + "/stretched";
    std::filesystem::create_directories(dir);
    write_tetgen(deformed, stem);
    for (const char* sw : {"-rO9/7Q", "-rqO9/7YQ"}) {
      std::filesystem::remove(stem + ".1.node");
      std::filesystem::remove(stem + ".1.ele");
      const auto t0 = Clock::now();
      const int rc = std::system(("cd " + dir + " && tetgen " + sw + " stretched > tetgen.log 2>&1").c_str());
      const double s = seconds_since(t0);
      Mesh out;
      const std::string name = std::string("tetgen ") + sw;
      if (rc != 0 || !read_tetgen(stem + ".1", out)) {
        std::printf("%-28s failed (exit %d, see %s/tetgen.log)\n", name.c_str(), rc, dir.c_str());
        continue;
      }
      print_row(name.c_str(), s, measure(out, boundary), femorph_s);
    }
    // Gmsh: optimize("") and optimize("Relocate3D"), the optimize call timed.
    const std::string msh = dir + "/stretched.msh", out_msh = dir + "/optimized.msh";
    write_msh2(deformed, msh);
    for (const char* method : {"", "Relocate3D"}) {
      const std::string cmd = std::string("/usr/bin/python3 ") + FEMORPH_BENCH_DIR + "/gmsh_optimize_peer.py " + msh +
                              " " + out_msh + " '" + method + "' 2>&1";
      const std::string log = run_capture(cmd);
      const auto at = log.rfind("seconds ");
      Mesh out;
      const std::string name = std::string("gmsh optimize ") + (*method ? method : "(default)");
      if (at == std::string::npos || !read_msh2(out_msh, out)) {
        std::printf("%-28s failed: %s\n", name.c_str(), log.substr(0, 200).c_str());
        continue;
      }
      print_row(name.c_str(), std::atof(log.c_str() + at + 8), measure(out, boundary), femorph_s);
    }
  }
  return 0;
}
