// Benchmark of FEMorph Segment (goals in docs/ARCHITECTURE.md): per-step
// times like thesis Table 2.9 for each Data/ part and for a fine part of
// about 200,000 boundary triangles, triangles per second of the core and of
// the filter vtkFEMorphSegment end to end (columns "filter"), and, in
// the same command, the peer: CGAL's Efficient RANSAC shape detection on the
// same boundary points and normals, with its time and the primitives it finds
// against the truth.
//
//   build/bin/bench_segment [--repeats=5] [--fine-dir=DIR] [--no-fine] [--no-cgal] [--only=PART]
//
// The fine part is made by Data/generate_parts.py (Gmsh) into --fine-dir
// (default: build/bench-data) the first time and reused afterwards.
#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphSegment.h"

#include "common/parallel.h"
#include "geometry/surface_primitive.h"
#include "mesh/surface_mesh.h"
#include "segment/segmentation.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#ifdef FEMORPH_HAVE_CGAL_PEER
#include "cgal_shape_detection.h"
#endif


#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace {

using femorph::SurfaceType;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

/// Count of distinct surfaces per type in a part's JSON: CAD faces of one
/// primitive with equal parameters count as one (as in the tests).
std::array<int, 6> truth_counts(const json& truth, double scale) {
  std::array<int, 6> counts{};
  std::vector<femorph::SurfacePrimitive> seen;
  auto vec = [](const json& j) { return femorph::Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()); };
  for (const json& f : truth["faces"]) {
    const std::string p = f["primitive"].get<std::string>();
    femorph::SurfacePrimitive s;
    if (p == "plane") {
      s.type = SurfaceType::Plane;
      s.point = vec(f["point"]);
      s.axis = vec(f["normal"]).normalized();
    } else if (p == "cylinder") {
      s.type = SurfaceType::Cylinder;
      s.point = vec(f["axis_point"]);
      s.axis = vec(f["axis_direction"]).normalized();
      s.radius = f["radius"];
    } else if (p == "cone") {
      s.type = SurfaceType::Cone;
      s.point = vec(f["apex"]);
      s.axis = vec(f["axis_direction"]).normalized();
      s.half_angle = f["half_angle_deg"].get<double>() * femorph::kPi / 180;
    } else if (p == "sphere") {
      s.type = SurfaceType::Sphere;
      s.point = vec(f["center"]);
      s.radius = f["radius"];
    } else if (p == "torus") {
      s.type = SurfaceType::Torus;
      s.point = vec(f["center"]);
      s.axis = vec(f["axis_direction"]).normalized();
      s.radius = f["major_radius"];
      s.minor_radius = f["minor_radius"];
    } else {
      ++counts[static_cast<int>(SurfaceType::Unknown)];
      continue;
    }
    bool dup = false;
    for (const auto& o : seen) dup = dup || femorph::same_surface(s, o, 1e-9, scale, 1e-9);
    if (!dup) {
      seen.push_back(s);
      ++counts[static_cast<int>(s.type)];
    }
  }
  return counts;
}

std::string counts_text(const std::array<int, 6>& c, bool with_unknown) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%d/%d/%d/%d/%d", c[0], c[1], c[2], c[3], c[4]);
  std::string s = buf;
  if (with_unknown) s += "+" + std::to_string(c[5]);
  return s;
}

struct Row {
  std::string name;
  int triangles = 0;
  femorph::SegmentationTimes times;  // medians per step
  double extract = 0;                // boundary extraction, median
  double total = 0;                  // extraction + segmentation, median
  double filter = 0;                 // vtkFEMorphSegment end to end (input grid to its outputs), median
  std::array<int, 6> found{}, truth{};
  int split_faces = 0, mixed_regions = 0;  // against CADFace
  double cgal_seconds = -1;
  std::array<int, 6> cgal{};
  int cgal_unassigned = 0;
};

Row run_part(const std::string& vtu, const std::string& name, int repeats, bool cgal) {
  Row row;
  row.name = name;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(vtu.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  femorph::TetMesh mesh;
  femorph::Status st = vtkFEMorphMeshConversion::ToTetMesh(grid, {}, mesh);
  if (!st.ok) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), st.message.c_str());
    std::exit(1);
  }
  double b[6];
  grid->GetBounds(b);
  const double scale = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));

  std::vector<double> t_extract, t_total, t_sharp, t_curv, t_planes, t_cyl, t_cones, t_spheres, t_tori, t_remaining,
      t_cleanup, t_refine, t_curves;
  femorph::SurfaceMesh surface;
  femorph::Segmentation seg;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    st = femorph::extract_boundary_surface(mesh, surface);
    const double extract = seconds_since(start);
    st = femorph::segment_surface(surface, femorph::SegmentationParams(), seg);
    if (!st.ok) {
      std::fprintf(stderr, "%s: %s\n", name.c_str(), st.message.c_str());
      std::exit(1);
    }
    t_total.push_back(seconds_since(start));
    t_extract.push_back(extract);
    const auto& T = seg.times;
    t_sharp.push_back(T.sharp_edges);
    t_curv.push_back(T.curvature);
    t_planes.push_back(T.planes);
    t_cyl.push_back(T.cylinders);
    t_cones.push_back(T.cones);
    t_spheres.push_back(T.spheres);
    t_tori.push_back(T.tori);
    t_remaining.push_back(T.remaining);
    t_cleanup.push_back(T.cleanup);
    t_refine.push_back(T.refinement);
    t_curves.push_back(T.curves);
  }
  // End to end through the filter, as ParaView runs it: conversion from the
  // grid, the segmentation, the output arrays, surface and table.
  std::vector<double> t_filter;
  for (int r = 0; r < repeats; ++r) {
    vtkNew<vtkFEMorphSegment> filter;
    filter->SetInputData(grid);
    const auto start = Clock::now();
    filter->Update();
    t_filter.push_back(seconds_since(start));
  }
  row.filter = median(t_filter);
  row.triangles = surface.num_triangles();
  row.extract = median(t_extract);
  row.total = median(t_total);
  row.times.sharp_edges = median(t_sharp);
  row.times.curvature = median(t_curv);
  row.times.planes = median(t_planes);
  row.times.cylinders = median(t_cyl);
  row.times.cones = median(t_cones);
  row.times.spheres = median(t_spheres);
  row.times.tori = median(t_tori);
  row.times.remaining = median(t_remaining);
  row.times.cleanup = median(t_cleanup);
  row.times.refinement = median(t_refine);
  row.times.curves = median(t_curves);
  for (const femorph::Region& r : seg.regions) ++row.found[static_cast<int>(r.type)];

  // Against the CAD: faces split over regions, regions holding faces of
  // different surfaces.
  const std::string json_path = vtu.substr(0, vtu.size() - 4) + ".json";
  json truth;
  if (std::ifstream in(json_path); in) truth = json::parse(in);
  vtkDataArray* cad = grid->GetCellData()->GetArray("CADFace");
  if (!truth.is_null()) row.truth = truth_counts(truth, scale);
  if (cad) {
    std::map<int, std::map<femorph::index_t, int>> face_regions;
    std::map<femorph::index_t, std::map<int, int>> region_faces;
    for (femorph::index_t f = 0; f < surface.num_triangles(); ++f) {
      const femorph::index_t code = surface.source_face[f];
      const int tag = static_cast<int>(cad->GetComponent(code >> 2, code & 3));
      ++face_regions[tag][seg.triangle_region[f]];
      ++region_faces[seg.triangle_region[f]][tag];
    }
    for (const auto& [tag, regions] : face_regions) row.split_faces += regions.size() > 1;
    (void)region_faces;
  }

#ifdef FEMORPH_HAVE_CGAL_PEER
  if (cgal) {
    // Boundary vertices with area-weighted normals, as CGAL expects a point
    // cloud with normals.
    std::vector<std::array<double, 3>> points(surface.points.size()), normals(surface.points.size());
    for (femorph::index_t v = 0; v < surface.num_points(); ++v) {
      femorph::Vec3 n = femorph::Vec3::Zero();
      for (femorph::index_t i = surface.vertex_offsets[v]; i < surface.vertex_offsets[v + 1]; ++i) {
        const femorph::index_t f = surface.vertex_triangles[i];
        n += surface.areas[f] * surface.normals[f];
      }
      n.normalize();
      points[v] = {surface.points[v].x(), surface.points[v].y(), surface.points[v].z()};
      normals[v] = {n.x(), n.y(), n.z()};
    }
    std::vector<double> t;
    femorph::bench::CgalShapeDetectionResult result;
    const int cgal_repeats = row.triangles > 50000 ? 1 : std::min(repeats, 3);
    for (int r = 0; r < cgal_repeats; ++r) {
      result = femorph::bench::cgal_efficient_ransac(points, normals);
      t.push_back(result.seconds);
    }
    if (result.ok) {
      row.cgal_seconds = median(t);
      for (int k = 0; k < femorph::bench::kCgalShapeTypeCount; ++k) row.cgal[k] = static_cast<int>(result.count_by_type[k]);
      row.cgal_unassigned = static_cast<int>(result.unassigned_points);
    }
  }
#else
  (void)cgal;
#endif
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 5;
  bool fine = true, cgal = true;
  std::string fine_dir = std::string(FEMORPH_BINARY_DIR) + "/bench-data";
  std::string only;  // one part by name (e.g. boss_block_fine), for profiling
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--repeats=", 10) == 0) repeats = std::max(1, std::atoi(argv[i] + 10));
    else if (std::strncmp(argv[i], "--fine-dir=", 11) == 0) fine_dir = argv[i] + 11;
    else if (std::strcmp(argv[i], "--no-fine") == 0) fine = false;
    else if (std::strcmp(argv[i], "--no-cgal") == 0) cgal = false;
    else if (std::strncmp(argv[i], "--only=", 7) == 0) only = argv[i] + 7;
    else {
      std::fprintf(stderr, "usage: %s [--repeats=N] [--fine-dir=DIR] [--no-fine] [--no-cgal] [--only=PART]\n", argv[0]);
      return 2;
    }
  }
  std::vector<std::pair<std::string, std::string>> parts;  // (name, .vtu)
  for (const auto& entry : std::filesystem::directory_iterator(FEMORPH_DATA_DIR)) {
    const std::filesystem::path p = entry.path();
    if (p.extension() == ".vtu" && std::filesystem::exists(std::filesystem::path(p).replace_extension(".json")))
      parts.emplace_back(p.stem().string(), p.string());
  }
  std::sort(parts.begin(), parts.end());
  if (fine && (only.empty() || only == "boss_block_fine")) {
    const std::string vtu = fine_dir + "/boss_block_fine.vtu";
    if (!std::filesystem::exists(vtu)) {
      std::printf("making the fine part with Gmsh into %s ...\n", fine_dir.c_str());
      std::fflush(stdout);
      const std::string cmd = "/usr/bin/python3 " + std::string(FEMORPH_DATA_DIR) +
                              "/generate_parts.py --fine boss_block --target-boundary-triangles 200000 --out-dir " +
                              fine_dir + " > " + fine_dir + ".log 2>&1";
      std::filesystem::create_directories(fine_dir);
      if (std::system(cmd.c_str()) != 0 || !std::filesystem::exists(vtu))
        std::printf("could not make the fine part (see %s.log); skipping it\n", fine_dir.c_str());
    }
    if (std::filesystem::exists(vtu)) parts.emplace_back("boss_block_fine", vtu);
  }

  if (!only.empty())
    parts.erase(std::remove_if(parts.begin(), parts.end(), [&](const auto& p) { return p.first != only; }), parts.end());
  std::printf("FEMorph Segment benchmark: %d threads, medians of %d runs (CGAL: of up to 3)\n", femorph::parallel_threads(),
              repeats);
  std::vector<Row> rows;
  for (const auto& [name, vtu] : parts) {
    std::printf("  %s ...\n", name.c_str());
    std::fflush(stdout);
    rows.push_back(run_part(vtu, name, repeats, cgal));
  }

  std::printf("\nPer-step times in ms (thesis Table 2.9 layout)\n");
  std::printf("%-18s %8s %7s %6s %6s %6s %6s %6s %6s %6s %6s %7s %6s %6s %8s %10s %8s %10s\n", "part", "tris",
              "extract", "sharp", "curv", "planes", "cyl", "cones", "sphere", "tori", "remain", "cleanup", "refine",
              "curves", "total", "tris/s", "filter", "filter/s");
  for (const Row& r : rows) {
    const auto& T = r.times;
    std::printf(
        "%-18s %8d %7.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %7.1f %6.1f %6.1f %8.1f %10.0f %8.1f %10.0f\n",
        r.name.c_str(), r.triangles, 1e3 * r.extract, 1e3 * T.sharp_edges, 1e3 * T.curvature, 1e3 * T.planes,
        1e3 * T.cylinders, 1e3 * T.cones, 1e3 * T.spheres, 1e3 * T.tori, 1e3 * T.remaining, 1e3 * T.cleanup,
        1e3 * T.refinement, 1e3 * T.curves, 1e3 * r.total, r.triangles / r.total, 1e3 * r.filter,
        r.triangles / r.filter);
  }
  std::printf("\nPrimitives found, plane/cylinder/cone/sphere/torus(+unknown); CAD faces split over regions\n");
  std::printf("%-18s %14s %14s %6s %14s %9s %9s %9s\n", "part", "truth", "FEMorph", "split", "CGAL", "CGAL s",
              "FEMorph s", "speedup");
  for (const Row& r : rows) {
    std::printf("%-18s %14s %14s %6d %14s %9.3f %9.3f %9.1f\n", r.name.c_str(), counts_text(r.truth, true).c_str(),
                counts_text(r.found, true).c_str(), r.split_faces,
                r.cgal_seconds >= 0 ? counts_text(r.cgal, false).c_str() : "-", r.cgal_seconds, r.total,
                r.cgal_seconds > 0 ? r.cgal_seconds / r.total : 0.0);
  }
  double all_tris = 0, all_time = 0, all_filter = 0;
  for (const Row& r : rows) {
    all_tris += r.triangles;
    all_time += r.total;
    all_filter += r.filter;
  }
  std::printf("\nall parts: %.0f triangles in %.3f s = %.0f triangles/s (goal >= 100,000/s)\n", all_tris, all_time,
              all_tris / all_time);
  std::printf("all parts through vtkFEMorphSegment (end to end): %.3f s = %.0f triangles/s\n", all_filter,
              all_tris / all_filter);
  return 0;
}
