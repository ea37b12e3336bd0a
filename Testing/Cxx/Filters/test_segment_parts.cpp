// Segmentation accuracy on the Data/ CAD parts (Segment's acceptance goals,
// docs/ARCHITECTURE.md): every boundary triangle lies in the region of its
// CAD face (faces of one primitive with equal parameters count as one), every
// region has the CAD face's type, and radii, axes, distances and angles match
// the construction within 1e-6 relative. The truth is the part's JSON, written from the construction by
// Data/generate_parts.py; the CAD face of each tet face is the CADFace array.
#include "vtkFEMorphMeshConversion.h"

#include "mesh/surface_mesh.h"
#include "segment/segmentation.h"

#include "vtkCellData.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <set>

namespace {

using femorph::SurfacePrimitive;
using femorph::SurfaceType;
using femorph::Vec3;
using json = nlohmann::json;

struct Part {
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  json truth;
  std::map<int, json> faces;  // by CAD tag
  double scale = 1;           // bounding box diagonal
};

Part load(const std::string& name) {
  Part part;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName((std::string(FEMORPH_DATA_DIR) + "/" + name + ".vtu").c_str());
  reader->Update();
  part.grid = reader->GetOutput();
  std::ifstream in(std::string(FEMORPH_DATA_DIR) + "/" + name + ".json");
  part.truth = json::parse(in);
  for (const json& f : part.truth["faces"]) part.faces[f["tag"].get<int>()] = f;
  double b[6];
  part.grid->GetBounds(b);
  part.scale = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  return part;
}

Vec3 vec(const json& j) { return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()); }

SurfaceType type_of(const json& face) {
  const std::string p = face["primitive"].get<std::string>();
  if (p == "plane") return SurfaceType::Plane;
  if (p == "cylinder") return SurfaceType::Cylinder;
  if (p == "cone") return SurfaceType::Cone;
  if (p == "sphere") return SurfaceType::Sphere;
  if (p == "torus") return SurfaceType::Torus;
  return SurfaceType::Unknown;
}

/// The construction surface of a CAD face, in the core's conventions.
SurfacePrimitive surface_of(const json& f) {
  SurfacePrimitive s;
  s.type = type_of(f);
  switch (s.type) {
    case SurfaceType::Plane: s.point = vec(f["point"]); s.axis = vec(f["normal"]); break;
    case SurfaceType::Cylinder: s.point = vec(f["axis_point"]); s.axis = vec(f["axis_direction"]); s.radius = f["radius"]; break;
    case SurfaceType::Cone:
      s.point = vec(f["apex"]);
      s.axis = vec(f["axis_direction"]);
      s.half_angle = f["half_angle_deg"].get<double>() * femorph::kPi / 180.0;
      break;
    case SurfaceType::Sphere: s.point = vec(f["center"]); s.radius = f["radius"]; break;
    case SurfaceType::Torus:
      s.point = vec(f["center"]);
      s.axis = vec(f["axis_direction"]);
      s.radius = f["major_radius"];
      s.minor_radius = f["minor_radius"];
      break;
    default: break;
  }
  s.axis.normalize();
  return s;
}

/// Distance from point p to the line through q along unit a.
double line_distance(const Vec3& p, const Vec3& q, const Vec3& a) { return ((p - q) - (p - q).dot(a) * a).norm(); }

/// Every parameter of `fit` matches `truth` within `rel` (lengths relative to
/// their size, positions relative to the part, angles in radians * rel).
void expect_same_surface(const SurfacePrimitive& fit, const SurfacePrimitive& truth, double rel, double scale,
                         const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(fit.type, truth.type);
  const double parallel = 1.0 - std::abs(fit.axis.normalized().dot(truth.axis));
  switch (truth.type) {
    case SurfaceType::Plane:
      EXPECT_LT(parallel, rel);
      EXPECT_LT(std::abs((truth.point - fit.point).dot(truth.axis)), rel * scale);  // same plane
      break;
    case SurfaceType::Cylinder:
      EXPECT_NEAR(fit.radius, truth.radius, rel * truth.radius);
      EXPECT_LT(parallel, rel);
      EXPECT_LT(line_distance(fit.point, truth.point, truth.axis), rel * scale);
      break;
    case SurfaceType::Cone:
      EXPECT_NEAR(fit.half_angle, truth.half_angle, rel * truth.half_angle);
      EXPECT_LT(parallel, rel);
      EXPECT_GT(fit.axis.dot(truth.axis), 0);
      EXPECT_LT((fit.point - truth.point).norm(), rel * scale);
      break;
    case SurfaceType::Sphere:
      EXPECT_NEAR(fit.radius, truth.radius, rel * truth.radius);
      EXPECT_LT((fit.point - truth.point).norm(), rel * scale);
      break;
    case SurfaceType::Torus:
      EXPECT_NEAR(fit.radius, truth.radius, rel * truth.radius);
      EXPECT_NEAR(fit.minor_radius, truth.minor_radius, rel * truth.minor_radius);
      EXPECT_LT(parallel, rel);
      EXPECT_LT((fit.point - truth.point).norm(), rel * scale);
      break;
    default: break;
  }
}

struct Result {
  femorph::SurfaceMesh surface;
  femorph::Segmentation seg;
  std::vector<int> triangle_cad;  // CAD tag per surface triangle
};

Result segment(vtkUnstructuredGrid* grid, const femorph::SegmentationParams& params) {
  Result r;
  femorph::TetMesh mesh;
  femorph::Status s = vtkFEMorphMeshConversion::ToTetMesh(grid, {}, mesh);
  EXPECT_TRUE(s.ok) << s.message;
  s = femorph::extract_boundary_surface(mesh, r.surface);
  EXPECT_TRUE(s.ok) << s.message;
  s = femorph::segment_surface(r.surface, params, r.seg);
  EXPECT_TRUE(s.ok) << s.message;
  vtkIntArray* cad = vtkIntArray::SafeDownCast(grid->GetCellData()->GetArray("CADFace"));
  EXPECT_NE(cad, nullptr);
  for (femorph::index_t code : r.surface.source_face)
    r.triangle_cad.push_back(cad ? static_cast<int>(cad->GetTypedComponent(code >> 2, code & 3)) : -1);
  return r;
}

/// The acceptance test for one part at relative accuracy `rel`.
void check_against_cad(const Part& part, const Result& r, double rel) {
  // CAD face -> regions and region -> CAD faces.
  std::map<int, std::map<femorph::index_t, int>> cad_regions;
  std::map<femorph::index_t, std::set<int>> region_cads;
  for (std::size_t f = 0; f < r.triangle_cad.size(); ++f) {
    ++cad_regions[r.triangle_cad[f]][r.seg.triangle_region[f]];
    region_cads[r.seg.triangle_region[f]].insert(r.triangle_cad[f]);
  }
  for (const auto& [tag, regions] : cad_regions) {
    std::string where;
    for (const auto& [region, n] : regions) where += " region " + std::to_string(region) + " (" + std::to_string(n) + ")";
    EXPECT_EQ(regions.size(), 1u) << "CAD face " << tag << " ("
                                  << part.faces.at(tag)["label"].get<std::string>() << ") is split:" << where;
  }
  for (const auto& [region_id, tags] : region_cads) {
    const femorph::Region& region = r.seg.regions[region_id];
    const json& first = part.faces.at(*tags.begin());
    const SurfacePrimitive truth = surface_of(first);
    const std::string label = "region " + std::to_string(region_id) + " = CAD face " + std::to_string(*tags.begin()) +
                              " (" + first["label"].get<std::string>() + ")";
    // Faces merged into one region must be one primitive.
    for (int tag : tags) {
      if (tag == *tags.begin()) continue;
      const SurfacePrimitive other = surface_of(part.faces.at(tag));
      EXPECT_TRUE(femorph::same_surface(truth, other, 1e-9, part.scale, 1e-9))
          << label << " also holds CAD face " << tag << " (" << part.faces.at(tag)["label"].get<std::string>()
          << "), a different surface";
    }
    EXPECT_EQ(region.type, truth.type) << label << ": " << femorph::to_string(region.type) << " instead of "
                                       << femorph::to_string(truth.type);
    if (region.type == truth.type && truth.type != SurfaceType::Unknown)
      expect_same_surface(region.surface, truth, rel, part.scale, label);
  }
}

class SegmentPart : public ::testing::TestWithParam<const char*> {};

TEST_P(SegmentPart, RegionsTypesAndParametersMatchTheCad) {
  const Part part = load(GetParam());
  const Result r = segment(part.grid, femorph::SegmentationParams());
  check_against_cad(part, r, 1e-6);
}

TEST_P(SegmentPart, JitteredVerticesKeepTypesAndRadiiWithin1e3) {
  // Every vertex moved at random by up to 1e-3 of its shortest incident
  // edge: types stay right and radii within 1e-3 relative.
  const Part part = load(GetParam());
  vtkNew<vtkUnstructuredGrid> jittered;
  jittered->DeepCopy(part.grid);
  const vtkIdType np = jittered->GetNumberOfPoints();
  std::vector<double> shortest(static_cast<std::size_t>(np), 1e300);
  for (vtkIdType c = 0; c < jittered->GetNumberOfCells(); ++c) {
    const vtkIdType* ids;
    vtkIdType n;
    jittered->GetCellPoints(c, n, ids);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        double a[3], b[3];
        jittered->GetPoint(ids[i], a);
        jittered->GetPoint(ids[j], b);
        const double d = std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
        shortest[ids[i]] = std::min(shortest[ids[i]], d);
        shortest[ids[j]] = std::min(shortest[ids[j]], d);
      }
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (vtkIdType p = 0; p < np; ++p) {
    double x[3];
    jittered->GetPoint(p, x);
    Vec3 d(u(rng), u(rng), u(rng));
    if (d.norm() > 1) d.normalize();
    for (int k = 0; k < 3; ++k) x[k] += 1e-3 * shortest[p] * d[k];
    jittered->GetPoints()->SetPoint(p, x);
  }
  femorph::SegmentationParams params;
  params.distance_tolerance = 1e-2;  // the jitter is 1e-3 of the edge length
  const Result r = segment(jittered, params);
  check_against_cad(part, r, 1e-3);
}

/// Accuracy of a segmentation against the CAD faces: the fraction of
/// triangles in the region of their own CAD face (the region holding most of
/// the face's triangles, whose own largest face is that face or one surface
/// with it) and the fraction in a region of their face's type.
struct Accuracy {
  double in_region = 0, typed = 0;
  std::string wrong;  // the CAD faces with triangles out of place or mistyped
};

Accuracy accuracy(const Part& part, const Result& r) {
  std::map<int, std::map<femorph::index_t, int>> cad_regions;
  std::map<femorph::index_t, std::map<int, int>> region_cads;
  for (std::size_t f = 0; f < r.triangle_cad.size(); ++f) {
    ++cad_regions[r.triangle_cad[f]][r.seg.triangle_region[f]];
    ++region_cads[r.seg.triangle_region[f]][r.triangle_cad[f]];
  }
  auto largest = [](const auto& counts) {
    auto best = counts.begin();
    for (auto it = counts.begin(); it != counts.end(); ++it)
      if (it->second > best->second) best = it;
    return best->first;
  };
  std::size_t in_region = 0, typed = 0;
  std::map<int, std::pair<int, int>> misses;  // tag -> (out of place, mistyped)
  std::map<int, std::string> as;              // tag -> a wrong type it got
  for (std::size_t f = 0; f < r.triangle_cad.size(); ++f) {
    const int tag = r.triangle_cad[f];
    const femorph::index_t region = r.seg.triangle_region[f];
    const SurfacePrimitive truth = surface_of(part.faces.at(tag));
    const bool type_ok = r.seg.regions[region].type == truth.type;
    typed += type_ok;
    misses[tag].second += !type_ok;
    if (!type_ok) as[tag] = femorph::to_string(r.seg.regions[region].type);
    const int owner = largest(region_cads[region]);
    const bool placed = largest(cad_regions[tag]) == region &&
                        (owner == tag ||
                         femorph::same_surface(truth, surface_of(part.faces.at(owner)), 1e-9, part.scale, 1e-9));
    in_region += placed;
    misses[tag].first += !placed;
  }
  const double n = static_cast<double>(r.triangle_cad.size());
  Accuracy a{static_cast<double>(in_region) / n, static_cast<double>(typed) / n, ""};
  for (const auto& [tag, m] : misses)
    if (m.first || m.second)
      a.wrong += "\n  CAD face " + std::to_string(tag) + " (" + part.faces.at(tag)["label"].get<std::string>() +
                 "): " + std::to_string(m.first) + " out of place, " + std::to_string(m.second) + " mistyped" +
                 (as.count(tag) ? " (e.g. as " + as[tag] + ")" : std::string());
  return a;
}

/// The part with its boundary-curve nodes (CADEntityDim 0 or 1) moved off
/// their faces by 1e-4 to 5e-4 of the bounding box diagonal in a random
/// direction, the nodes inside faces left exact: how a mesh made from a STEP
/// file looks, whose edge curves are approximations of the face
/// intersections. Seam curves (one adjacent face: a line or
/// circle of the surface itself) stay exact.
vtkSmartPointer<vtkUnstructuredGrid> approximate_curves(const Part& part) {
  vtkNew<vtkUnstructuredGrid> out;
  out->DeepCopy(part.grid);
  vtkIntArray* dim = vtkIntArray::SafeDownCast(out->GetPointData()->GetArray("CADEntityDim"));
  vtkIntArray* tag = vtkIntArray::SafeDownCast(out->GetPointData()->GetArray("CADEntityTag"));
  EXPECT_NE(dim, nullptr);
  EXPECT_NE(tag, nullptr);
  std::set<int> seams;
  for (const json& c : part.truth["curves"])
    if (c["surfaces"].size() < 2) seams.insert(c["tag"].get<int>());
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(1e-4, 5e-4);
  for (vtkIdType p = 0; dim && tag && p < out->GetNumberOfPoints(); ++p) {
    if (dim->GetValue(p) > 1 || (dim->GetValue(p) == 1 && seams.count(tag->GetValue(p)))) continue;
    Vec3 d;
    do d = Vec3(u(rng), u(rng), u(rng));
    while (d.norm() > 1 || d.norm() < 1e-3);
    d *= size(rng) * part.scale / d.norm();
    double x[3];
    out->GetPoint(p, x);
    for (int k = 0; k < 3; ++k) x[k] += d[k];
    out->GetPoints()->SetPoint(p, x);
  }
  return out;
}

class SegmentPartApproximateCurves : public ::testing::TestWithParam<const char*> {};

TEST_P(SegmentPartApproximateCurves, AtDefaults) {
  // Segment's goals on CAD meshes (docs/ARCHITECTURE.md) at the defaults: >= 99.9% of the triangles in
  // the region of their CAD face, >= 99.5% in a region of its type.
  const Part part = load(GetParam());
  const Result r = segment(approximate_curves(part), femorph::SegmentationParams());
  const Accuracy a = accuracy(part, r);
  std::size_t unknown = 0;
  for (const femorph::Region& region : r.seg.regions) unknown += region.type == SurfaceType::Unknown;
  std::cout << GetParam() << ": " << r.triangle_cad.size() << " triangles, " << a.in_region << " in region, "
            << a.typed << " typed, " << r.seg.regions.size() << " regions (" << unknown << " unknown)\n";
  EXPECT_GE(a.in_region, 0.999) << a.wrong;
  EXPECT_GE(a.typed, 0.995) << a.wrong;
}

INSTANTIATE_TEST_SUITE_P(DataParts, SegmentPartApproximateCurves,
                         ::testing::Values("boss_block", "filleted_box", "cone_sphere_torus", "fillet_junctions",
                                           "bspline_face"));

INSTANTIATE_TEST_SUITE_P(DataParts, SegmentPart,
                         ::testing::Values("boss_block", "filleted_box", "cone_sphere_torus", "fillet_junctions",
                                           "bspline_face"));

}  // namespace
