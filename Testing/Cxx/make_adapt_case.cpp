// Writes the contact case of thesis 3.7.3 (a cylinder translated along its
// axis into a half tube of the same radius, Testing/Cxx/test_adapt_meshes.h's
// make_cylinder_half_tube) as Data/adapt/cylinder_half_tube.vtu (ASCII VTK
// XML: Float64 points, positive VTK_TETRA cells, cell array MaterialId
// Int32: 0 space, 1 the cylinder, 2 the half tube) and a .json beside it
// with the geometry, the motion and the contact areas per step.
// With --assembly, thesis 3.7.4's kind of case instead
// (test_adapt_meshes.h's make_crank_assembly): a crank (MaterialId 1) in a
// bearing's bore (MaterialId 2), meshed separately, non-conforming, no
// space mesh (Data/adapt/assembly_crank.vtu).
//
//   make_adapt_case OUT.vtu [--r R] [--R R] [--Lc L] [--Lt L] [--gap G]
//                   [--n-theta N] [--margin M] [--space-edge E] [--steps S]
//                   [--benchmark] [--no-improve]
//   make_adapt_case OUT.vtu --assembly [--r R] [--R R] [--Lc L] [--Lb L]
//                   [--n-crank N] [--n-bearing N] [--benchmark]
//
// Deterministic (TetGen is): the same options give the same bytes.
#include "quality/tet_quality.h"
#include "test_adapt_meshes.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

using namespace femorph;

namespace {

bool write_vtu(const std::string& path, const testing::MaterialMesh& m) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f,
               "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
               "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n"
               "<Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n<CellData>\n"
               "<DataArray type=\"Int32\" Name=\"MaterialId\" format=\"ascii\">\n",
               m.points.size(), m.tets.size());
  for (std::size_t t = 0; t < m.material.size(); ++t)
    std::fprintf(f, "%d%c", m.material[t], t % 20 == 19 ? '\n' : ' ');
  std::fprintf(f, "\n</DataArray>\n</CellData>\n<Points>\n"
                  "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (const Vec3& p : m.points) std::fprintf(f, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  std::fprintf(f, "</DataArray>\n</Points>\n<Cells>\n"
                  "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (const Tet& t : m.tets) std::fprintf(f, "%d %d %d %d\n", t[0], t[1], t[2], t[3]);
  std::fprintf(f, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    std::fprintf(f, "%zu%c", 4 * (t + 1), t % 20 == 19 ? '\n' : ' ');
  std::fprintf(f, "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (std::size_t t = 0; t < m.tets.size(); ++t) std::fprintf(f, "10%c", t % 40 == 39 ? '\n' : ' ');
  std::fprintf(f, "\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
  return std::fclose(f) == 0;
}

std::string json_path(const std::string& out) {
  return out.substr(0, out.size() - (out.size() > 4 && out.substr(out.size() - 4) == ".vtu" ? 4 : 0)) + ".json";
}

// Thesis 3.7.4's kind of case: the crank turns 10 degrees per step about
// its axis (z), 36 steps.
int make_assembly(const std::string& out, int argc, char** argv) {
  testing::CrankAssembly g;
  std::string command = "make_adapt_case " + out + " --assembly";
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    command += " " + a;
    if (a == "--benchmark") {
      g = testing::CrankAssembly::benchmark();
      continue;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "%s needs a value\n", a.c_str());
      return 2;
    }
    const char* v = argv[++i];
    command += std::string(" ") + v;
    if (a == "--r") g.r = std::atof(v);
    else if (a == "--R") g.R = std::atof(v);
    else if (a == "--Lc") g.Lc = std::atof(v);
    else if (a == "--Lb") g.Lb = std::atof(v);
    else if (a == "--n-crank") g.n_crank = std::atoi(v);
    else if (a == "--n-bearing") g.n_bearing = std::atoi(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  Status status;
  const testing::MaterialMesh m = testing::make_crank_assembly(g, &status);
  if (!status) {
    std::fprintf(stderr, "%s\n", status.message.c_str());
    return 1;
  }
  if (!write_vtu(out, m)) {
    std::fprintf(stderr, "cannot write %s\n", out.c_str());
    return 1;
  }
  std::size_t count[3] = {0, 0, 0};
  double volume[3] = {0, 0, 0}, smin = 1, ssum = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const Tet& T = m.tets[t];
    const Vec3 &a = m.points[T[0]], &b = m.points[T[1]], &c = m.points[T[2]], &d = m.points[T[3]];
    ++count[m.material[t]];
    volume[m.material[t]] += (b - a).dot((c - a).cross(d - a)) / 6;
    const double s = tet_stretch(a, b, c, d);
    smin = std::min(smin, s);
    ssum += s;
  }
  FILE* f = std::fopen(json_path(out).c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "cannot write %s\n", json_path(out).c_str());
    return 1;
  }
  std::fprintf(f, "{\n \"description\": \"thesis 3.7.4: an assembly without space mesh, parts meshed separately "
                  "(non-conforming): a crank shaft (MaterialId 1, moving: a cylinder about the z axis, its polygon "
                  "turned by half a segment) lying in the bore of a bearing (MaterialId 2, fixed: a half tube, y <= "
                  "0); each meshed by TetGen -pYq from an exact surface triangulation of its own spacing\",\n");
  std::fprintf(f, " \"r\": %.17g,\n \"R\": %.17g,\n \"Lc\": %.17g,\n \"Lb\": %.17g,\n", g.r, g.R, g.Lc, g.Lb);
  std::fprintf(f, " \"n_crank\": %d,\n \"n_bearing\": %d,\n \"crank_edge\": %.17g,\n \"bearing_edge\": %.17g,\n",
               g.n_crank, g.n_bearing, g.crank_edge(), g.bearing_edge());
  std::fprintf(f, " \"crank\": {\"material_id\": 1, \"z\": [%.17g, %.17g]},\n", -0.5 * g.Lc, 0.5 * g.Lc);
  std::fprintf(f, " \"bearing\": {\"material_id\": 2, \"z\": [%.17g, %.17g]},\n", -0.5 * g.Lb, 0.5 * g.Lb);
  std::fprintf(f, " \"object\": {\"material_id\": 1, \"center\": [0, 0, 0]},\n");
  std::fprintf(f, " \"contact_materials\": [1, 2],\n \"space_material_id\": null,\n");
  std::fprintf(f, " \"motion_3_7_4\": {\"translation_per_step\": [0, 0, 0], \"rotation_axis\": [0, 0, 1], "
                  "\"rotation_center\": [0, 0, 0], \"rotation_degrees_per_step\": 10, \"steps\": 36},\n");
  std::fprintf(f, " \"contact_area\": {\"note\": \"once conformal: the bore's half polygon, n_bearing / 2 chords "
                  "over Lb\", \"discrete\": %.17g, \"exact\": %.17g},\n",
               g.contact_area(), kPi * g.r * g.Lb);
  std::fprintf(f, " \"counts\": {\"points\": %zu, \"tets\": %zu, \"crank_tets\": %zu, \"bearing_tets\": %zu},\n",
               m.points.size(), m.tets.size(), count[1], count[2]);
  std::fprintf(f, " \"volume\": {\"crank\": %.17g, \"bearing\": %.17g},\n", volume[1], volume[2]);
  std::fprintf(f, " \"quality\": {\"stretch_min\": %.17g, \"stretch_mean\": %.17g},\n", smin,
               ssum / static_cast<double>(m.tets.size()));
  std::fprintf(f, " \"orientation\": \"VTK_TETRA, (p1-p0).((p2-p0)x(p3-p0)) > 0 for every tet\",\n");
  std::fprintf(f, " \"generator\": \"%s\"\n}\n", command.c_str());
  std::fclose(f);
  std::printf("%s: %zu points, %zu tets (crank %zu, bearing %zu), stretch min %.3f mean %.3f\n", out.c_str(),
              m.points.size(), m.tets.size(), count[1], count[2], smin, ssum / static_cast<double>(m.tets.size()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr,
                 "usage: %s OUT.vtu [--r R] [--R R] [--Lc L] [--Lt L] [--gap G] [--n-theta N] "
                 "[--margin M] [--space-edge E] [--steps S] [--benchmark] [--no-improve]\n"
                 "       %s OUT.vtu --assembly [--r R] [--R R] [--Lc L] [--Lb L] [--n-crank N] [--n-bearing N] "
                 "[--benchmark]\n",
                 argv[0], argv[0]);
    return 2;
  }
  const std::string out = argv[1];
  if (argc > 2 && std::strcmp(argv[2], "--assembly") == 0) return make_assembly(out, argc, argv);
  testing::CylinderHalfTube g;
  int steps = -1;
  std::string command = "make_adapt_case " + out;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    command += " " + a;
    if (a == "--benchmark") {
      g = testing::CylinderHalfTube::benchmark();
      continue;
    }
    if (a == "--no-improve") {
      g.improve = false;
      continue;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "%s needs a value\n", a.c_str());
      return 2;
    }
    const char* v = argv[++i];
    command += std::string(" ") + v;
    if (a == "--r") g.r = std::atof(v);
    else if (a == "--R") g.R = std::atof(v);
    else if (a == "--Lc") g.Lc = std::atof(v);
    else if (a == "--Lt") g.Lt = std::atof(v);
    else if (a == "--gap") g.gap = std::atof(v);
    else if (a == "--n-theta") g.n_theta = std::atoi(v);
    else if (a == "--margin") g.margin = std::atof(v);
    else if (a == "--space-edge") g.space_edge = std::atof(v);
    else if (a == "--steps") steps = std::atoi(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  // The motion (3.7.3): 1 along +z per step; by default until the front cap
  // reaches the tube's far end (the box holds the cylinder until then).
  if (steps < 0) steps = static_cast<int>(std::ceil(g.Lt + g.gap));
  g.travel = steps;
  Status status;
  const testing::MaterialMesh m = testing::make_cylinder_half_tube(g, &status);
  if (!status) {
    std::fprintf(stderr, "%s\n", status.message.c_str());
    return 1;
  }
  if (!write_vtu(out, m)) {
    std::fprintf(stderr, "cannot write %s\n", out.c_str());
    return 1;
  }
  std::size_t count[3] = {0, 0, 0};
  double volume[3] = {0, 0, 0}, smin = 1, ssum = 0;
  Vec3 lo = m.points[0], hi = lo;
  for (const Vec3& p : m.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const Tet& T = m.tets[t];
    const Vec3 &a = m.points[T[0]], &b = m.points[T[1]], &c = m.points[T[2]], &d = m.points[T[3]];
    ++count[m.material[t]];
    volume[m.material[t]] += (b - a).dot((c - a).cross(d - a)) / 6;
    const double s = tet_stretch(a, b, c, d);
    smin = std::min(smin, s);
    ssum += s;
  }
  const std::string json = json_path(out);
  FILE* f = std::fopen(json.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "cannot write %s\n", json.c_str());
    return 1;
  }
  std::fprintf(f, "{\n \"description\": \"thesis 3.7.3: a cylinder (MaterialId 1, moving) translated 1 per step "
                  "along its axis z into a half tube (MaterialId 2, fixed; y <= 0) of the same inner radius, in a "
                  "box of space tets (MaterialId 0); objects meshed by TetGen -pYq from exact surface "
                  "triangulations, space by mesh_space_around%s\",\n",
               g.improve ? "; then each material's tets improved with every boundary and interface vertex fixed "
                           "(improve_material_mesh: Phased ODT smoothing and flips)"
                         : "");
  std::fprintf(f, " \"r\": %.17g,\n \"R\": %.17g,\n \"Lc\": %.17g,\n \"Lt\": %.17g,\n \"gap\": %.17g,\n",
               g.r, g.R, g.Lc, g.Lt, g.gap);
  std::fprintf(f, " \"n_theta\": %d,\n \"n_outer_half\": %d,\n \"margin\": %.17g,\n \"surface_edge\": %.17g,\n",
               g.n_theta, g.n_outer_half(), g.margin, g.edge());
  std::fprintf(f, " \"cylinder\": {\"material_id\": 1, \"z\": [%.17g, %.17g], \"volume\": %.17g},\n",
               -g.Lc - g.gap, -g.gap, g.cylinder_volume());
  std::fprintf(f, " \"half_tube\": {\"material_id\": 2, \"z\": [0, %.17g], \"volume\": %.17g},\n", g.Lt,
               g.half_tube_volume());
  std::fprintf(f, " \"object\": {\"material_id\": 1, \"center\": [0, 0, %.17g]},\n", -0.5 * g.Lc - g.gap);
  std::fprintf(f, " \"contact_materials\": [1, 2],\n");
  std::fprintf(f, " \"space_material_id\": 0,\n");
  std::fprintf(f, " \"domain\": {\"min\": [%.17g, %.17g, %.17g], \"max\": [%.17g, %.17g, %.17g]},\n", lo.x(), lo.y(),
               lo.z(), hi.x(), hi.y(), hi.z());
  std::fprintf(f, " \"motion_3_7_3\": {\"translation_per_step\": [0, 0, 1], \"rotation_axis\": [1, 0, 0], "
                  "\"rotation_center\": [0, 0, 0], \"rotation_degrees_per_step\": 0, \"steps\": %d},\n",
               steps);
  std::fprintf(f, " \"contact_area\": {\"note\": \"per step n (translation n): overlap = |[n - gap - Lc, n - gap] "
                  "and [0, Lt]|; exact = pi r overlap; discrete = n_half 2 r sin(pi / (2 n_half)) overlap (the "
                  "polygons' area, the one the 1%% check uses)\",\n  \"exact\": [");
  for (int n = 0; n <= steps; ++n)
    std::fprintf(f, "%.17g%s", testing::cylinder_half_tube_contact_area(g, n).exact, n < steps ? ", " : "");
  std::fprintf(f, "],\n  \"discrete\": [");
  for (int n = 0; n <= steps; ++n)
    std::fprintf(f, "%.17g%s", testing::cylinder_half_tube_contact_area(g, n).discrete, n < steps ? ", " : "");
  std::fprintf(f, "]},\n");
  std::fprintf(f, " \"counts\": {\"points\": %zu, \"tets\": %zu, \"space_tets\": %zu, \"cylinder_tets\": %zu, "
                  "\"half_tube_tets\": %zu},\n",
               m.points.size(), m.tets.size(), count[0], count[1], count[2]);
  std::fprintf(f, " \"volume\": {\"space\": %.17g, \"cylinder\": %.17g, \"half_tube\": %.17g},\n", volume[0],
               volume[1], volume[2]);
  std::fprintf(f, " \"quality\": {\"stretch_min\": %.17g, \"stretch_mean\": %.17g},\n", smin,
               ssum / static_cast<double>(m.tets.size()));
  std::fprintf(f, " \"orientation\": \"VTK_TETRA, (p1-p0).((p2-p0)x(p3-p0)) > 0 for every tet\",\n");
  std::fprintf(f, " \"generator\": \"%s\"\n}\n", command.c_str());
  std::fclose(f);
  std::printf("%s: %zu points, %zu tets (space %zu, cylinder %zu, half tube %zu), stretch min %.3f mean %.3f\n",
              out.c_str(), m.points.size(), m.tets.size(), count[0], count[1], count[2], smin,
              ssum / static_cast<double>(m.tets.size()));
  return 0;
}
