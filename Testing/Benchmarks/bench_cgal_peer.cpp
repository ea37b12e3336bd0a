// Smoke test of the benchmark's CGAL peer: Efficient RANSAC on the boundary
// vertices of parts (points, normals and CAD truth written by
// boundary_points_normals.py, since the benchmarks do not link VTK), against
// the CAD truth.
//
//   for p in boss_block filleted_box cone_sphere_torus; do
//     /usr/bin/python3 Testing/Benchmarks/boundary_points_normals.py Data/$p.vtu /tmp/$p.txt
//   done
//   build/bin/bench_cgal_peer [--repeat=3] [--epsilon=0.0005] [--cluster-epsilon=0.05]
//       [--min-points=0.002] [--probability=0.05] [--normal-threshold=0.99] [--seed=1]
//       [--max-radius=1] [--types=pckst] [--shapes] /tmp/*.txt
//
// Per part: the median time of the repeats (whole call, and CGAL's detect()
// alone), shapes found per type against the CAD faces per type ("found/true"),
// how many CAD faces were recovered (a shape of the face's type whose points
// lie mostly on that face, one shape per face), how many of those also have
// their radii / half angle / plane within 1%, and the share of points left
// unassigned. Relative parameters as in CgalRansacParameters.
#include "cgal_shape_detection.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using femorph::bench::CgalRansacParameters;
using femorph::bench::CgalShapeDetectionResult;
using femorph::bench::CgalShapeType;
using femorph::bench::kCgalShapeTypeCount;

const char* kTypeNames[] = {"plane", "cylinder", "cone", "sphere", "torus", "unknown"};
constexpr int kUnknown = 5;

int type_code(const std::string& name) {
  for (int k = 0; k < 6; ++k)
    if (name == kTypeNames[k]) return k;
  return kUnknown;
}

struct Part {
  std::string name;
  std::map<int, int> face_type;  // CAD face tag -> type code
  std::map<int, std::vector<double>> face_size;  // tag -> sizes (see boundary_points_normals.py)
  std::vector<std::array<double, 3>> points, normals;
  std::vector<int> tags;  // CAD face of each point, -1 on curves and corners
};

bool read_part(const std::string& path, Part& part, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot open " + path;
    return false;
  }
  std::string line, word;
  std::getline(in, line);  // "# FEMorph boundary points and normals v1 <name>"
  const std::string magic = "# FEMorph boundary points and normals v1 ";
  if (line.compare(0, magic.size(), magic) != 0) {
    error = path + ": not a FEMorph points and normals file";
    return false;
  }
  part.name = line.substr(magic.size());
  std::size_t count = 0;
  in >> word >> count;
  if (word != "faces") {
    error = path + ": expected 'faces'";
    return false;
  }
  std::getline(in, line);
  for (std::size_t i = 0; i < count; ++i) {
    std::getline(in, line);
    std::istringstream fields(line);
    int tag;
    std::string type;
    fields >> tag >> type;
    part.face_type[tag] = type_code(type);
    double v;
    while (fields >> v) part.face_size[tag].push_back(v);
  }
  in >> word >> count;
  if (word != "points" || !in) {
    error = path + ": expected 'points'";
    return false;
  }
  part.points.resize(count);
  part.normals.resize(count);
  part.tags.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    auto& p = part.points[i];
    auto& n = part.normals[i];
    in >> p[0] >> p[1] >> p[2] >> n[0] >> n[1] >> n[2] >> part.tags[i];
  }
  if (!in) {
    error = path + ": truncated";
    return false;
  }
  return true;
}

// Whether a shape's sizes match the CAD face's within `tolerance` relative:
// radius (cylinder, sphere), major and minor radius (torus), half angle
// (cone); plane: normal within tolerance radians and offset within tolerance
// times the diagonal.
bool sizes_match(const femorph::bench::CgalShape& s, const std::vector<double>& t,
                 double tolerance, double diagonal) {
  auto close = [&](double a, double b) { return std::abs(a - b) <= tolerance * std::abs(b); };
  switch (s.type) {
    case CgalShapeType::Plane: {
      if (t.size() < 4) return false;
      const double dot = s.normal[0] * t[0] + s.normal[1] * t[1] + s.normal[2] * t[2];
      const double sign = dot < 0 ? -1.0 : 1.0;
      return std::abs(dot) >= std::cos(tolerance) &&
             std::abs(sign * s.offset - t[3]) <= tolerance * diagonal;
    }
    case CgalShapeType::Cylinder:
    case CgalShapeType::Sphere: return t.size() >= 1 && close(s.radius, t[0]);
    case CgalShapeType::Cone: return t.size() >= 1 && close(s.half_angle_deg, t[0]);
    case CgalShapeType::Torus:
      return t.size() >= 2 && close(s.major_radius, t[0]) && close(s.minor_radius, t[1]);
  }
  return false;
}

// CAD faces recovered: each shape votes for the CAD face most of its
// surface-classified points lie on; a face counts once, when a shape of its
// type voted for it ([0..5], by type), and again in [6] when that shape's
// sizes also match within 1%.
std::array<int, 7> recovered_faces(const Part& part, const CgalShapeDetectionResult& r) {
  std::array<int, 7> found{};
  std::map<int, bool> taken;
  for (const auto& s : r.shapes) {
    std::map<int, std::size_t> votes;
    for (std::size_t i : s.indices)
      if (part.tags[i] >= 0) ++votes[part.tags[i]];
    if (votes.empty()) continue;
    const auto best = std::max_element(votes.begin(), votes.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    const auto it = part.face_type.find(best->first);
    if (it == part.face_type.end() || it->second != static_cast<int>(s.type)) continue;
    if (taken[best->first]) continue;
    taken[best->first] = true;
    ++found[it->second];
    const auto size = part.face_size.find(best->first);
    if (size != part.face_size.end() && sizes_match(s, size->second, 0.01, r.bbox_diagonal))
      ++found[6];
  }
  return found;
}

bool parse_double(const char* arg, const char* name, double& value) {
  const std::size_t n = std::strlen(name);
  if (std::strncmp(arg, name, n) != 0 || arg[n] != '=') return false;
  value = std::atof(arg + n + 1);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CgalRansacParameters parameters;
  int repeat = 3;
  bool print_shapes = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    double v = 0;
    if (parse_double(argv[i], "--repeat", v)) repeat = std::max(1, static_cast<int>(v));
    else if (parse_double(argv[i], "--epsilon", v)) parameters.epsilon_relative = v;
    else if (parse_double(argv[i], "--cluster-epsilon", v)) parameters.cluster_epsilon_relative = v;
    else if (parse_double(argv[i], "--min-points", v)) parameters.min_points_fraction = v;
    else if (parse_double(argv[i], "--probability", v)) parameters.probability = v;
    else if (parse_double(argv[i], "--normal-threshold", v)) parameters.normal_threshold = v;
    else if (parse_double(argv[i], "--seed", v)) parameters.seed = static_cast<unsigned>(v);
    else if (parse_double(argv[i], "--max-radius", v)) parameters.max_radius_relative = v;
    else if (std::strcmp(argv[i], "--shapes") == 0) print_shapes = true;
    else if (std::strncmp(argv[i], "--types=", 8) == 0) {
      const std::string t = argv[i] + 8;  // letters: p plane, c cylinder, k cone, s sphere, t torus
      parameters.planes = t.find('p') != std::string::npos;
      parameters.cylinders = t.find('c') != std::string::npos;
      parameters.cones = t.find('k') != std::string::npos;
      parameters.spheres = t.find('s') != std::string::npos;
      parameters.tori = t.find('t') != std::string::npos;
    }
    else if (argv[i][0] == '-') {
      std::fprintf(stderr, "unknown option %s (see the comment at the top of %s)\n", argv[i],
                   __FILE__);
      return 2;
    } else files.push_back(argv[i]);
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: %s [options] part.txt ... (see %s)\n", argv[0], __FILE__);
    return 2;
  }

  std::printf("CGAL Efficient RANSAC (planes, cylinders, cones, spheres, tori): probability %g, "
              "min_points %g of the points (>= %zu), epsilon %g and cluster_epsilon %g of the "
              "bbox diagonal, normal_threshold %g, seed %u; median of %d runs\n",
              parameters.probability, parameters.min_points_fraction,
              parameters.min_points_at_least, parameters.epsilon_relative,
              parameters.cluster_epsilon_relative, parameters.normal_threshold, parameters.seed,
              repeat);
  std::printf("%-20s %8s %8s %8s %8s  %-9s %-9s %-9s %-9s %-9s %-7s  %9s %9s %7s\n", "part",
              "points", "total s", "detect s", "pts/s", "plane", "cylinder", "cone", "sphere",
              "torus", "unknown", "recovered", "within1%", "unassig");
  int status = 0;
  for (const auto& file : files) {
    Part part;
    std::string error;
    if (!read_part(file, part, error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      status = 1;
      continue;
    }
    std::vector<CgalShapeDetectionResult> runs;
    for (int k = 0; k < repeat; ++k)
      runs.push_back(femorph::bench::cgal_efficient_ransac(part.points, part.normals, parameters));
    if (!runs[0].ok) {
      std::fprintf(stderr, "%s: %s\n", part.name.c_str(), runs[0].message.c_str());
      status = 1;
      continue;
    }
    std::vector<std::size_t> order(runs.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return runs[a].seconds < runs[b].seconds; });
    const CgalShapeDetectionResult& r = runs[order[order.size() / 2]];

    std::array<int, 6> truth{};
    for (const auto& [tag, type] : part.face_type) ++truth[type];
    const auto recovered = recovered_faces(part, r);
    int recovered_total = 0;
    for (int k = 0; k < 6; ++k) recovered_total += recovered[k];  // [6] is a subset

    char cells[6][32];
    for (int k = 0; k < 6; ++k) {
      const std::size_t found = k < kCgalShapeTypeCount ? r.count_by_type[k] : 0;
      if (k < kCgalShapeTypeCount)
        std::snprintf(cells[k], sizeof cells[k], "%zu/%d", found, truth[k]);
      else
        std::snprintf(cells[k], sizeof cells[k], "-/%d", truth[k]);
    }
    char rec[32];
    std::snprintf(rec, sizeof rec, "%d/%zu", recovered_total, part.face_type.size());
    char rec1[32];
    std::snprintf(rec1, sizeof rec1, "%d/%zu", recovered[6], part.face_type.size());
    std::printf("%-20s %8zu %8.3f %8.3f %8.0f  %-9s %-9s %-9s %-9s %-9s %-7s  %9s %9s %6.1f%%\n",
                part.name.c_str(), part.points.size(), r.seconds, r.detect_seconds,
                part.points.size() / r.seconds, cells[0], cells[1], cells[2], cells[3], cells[4],
                cells[5], rec, rec1, 100.0 * r.unassigned_points / part.points.size());
    if (print_shapes) {
      for (const auto& s : r.shapes) {
        std::printf("    %-8s %6zu pts", femorph::bench::cgal_shape_type_name(s.type),
                    s.indices.size());
        switch (s.type) {
          case CgalShapeType::Plane:
            std::printf("  normal (%.4f %.4f %.4f) offset %.6g", s.normal[0], s.normal[1],
                        s.normal[2], s.offset);
            break;
          case CgalShapeType::Cylinder:
            std::printf("  radius %.6g axis (%.4f %.4f %.4f)", s.radius, s.axis[0], s.axis[1],
                        s.axis[2]);
            break;
          case CgalShapeType::Cone:
            std::printf("  half angle %.6g deg apex (%.4g %.4g %.4g)", s.half_angle_deg,
                        s.point[0], s.point[1], s.point[2]);
            break;
          case CgalShapeType::Sphere:
            std::printf("  radius %.6g centre (%.4g %.4g %.4g)", s.radius, s.point[0],
                        s.point[1], s.point[2]);
            break;
          case CgalShapeType::Torus:
            std::printf("  major %.6g minor %.6g centre (%.4g %.4g %.4g)", s.major_radius,
                        s.minor_radius, s.point[0], s.point[1], s.point[2]);
            break;
        }
        std::printf("\n");
      }
    }
  }
  return status;
}
