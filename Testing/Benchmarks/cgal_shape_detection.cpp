// CGAL's Efficient RANSAC as the benchmark's peer; see cgal_shape_detection.h.
#include "cgal_shape_detection.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

namespace femorph {
namespace bench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// CGAL reorders the input range in preprocess()/detect() and reports shapes'
// points as positions in the reordered range: each element carries its
// original index.
using PointWithNormal = std::tuple<Kernel::Point_3, Kernel::Vector_3, std::size_t>;
using PointVector = std::vector<PointWithNormal>;
using PointMap = CGAL::Nth_of_tuple_property_map<0, PointWithNormal>;
using NormalMap = CGAL::Nth_of_tuple_property_map<1, PointWithNormal>;
using Traits = CGAL::Shape_detection::Efficient_RANSAC_traits<Kernel, PointVector, PointMap,
                                                              NormalMap>;
using Ransac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;
using Plane = CGAL::Shape_detection::Plane<Traits>;
using Cylinder = CGAL::Shape_detection::Cylinder<Traits>;
using Cone = CGAL::Shape_detection::Cone<Traits>;
using Sphere = CGAL::Shape_detection::Sphere<Traits>;
using Torus = CGAL::Shape_detection::Torus<Traits>;

// Guards against crashes in CGAL 5.5. Each detected candidate's points are
// clustered on a bitmap over the shape's 2D parameter space
// (Shape_base::connected_component), sized (max - min) / cluster_epsilon per
// direction, with no check. Our parts produce candidates that break it:
// (1) a point at a cone's apex or on a cylinder's axis (cylinders of radius ~0
// around a straight row of mesh vertices, cones whose apex is a vertex) gets
// NaN parameters, the bitmap extent becomes size_t(NaN), and std::length_error
// or a segfault follows; (2) a huge-radius cylinder fitted to a nearly flat
// patch that straddles the angle origin spans 2 pi radius / cluster_epsilon
// cells. SafeBitmap maps non-finite parameters to the minimum corner and, if
// the bitmap would still exceed kMaxBitmapCells, coarsens cluster_epsilon for
// that candidate only (not for spheres). RadiusLimited also rejects cylinder and sphere
// candidates with a radius outside [epsilon, max_radius] at creation: below
// epsilon they are a line or a point, and the radius limits are what other
// RANSAC front ends (CloudCompare) offer too.
constexpr double kMaxBitmapCells = double(1 << 24);

template <class Base, bool kMayCoarsen = true>
class SafeBitmap : public Base {
 protected:
  using FT = typename Base::FT;
  void parameters(const std::vector<std::size_t>& indices,
                  std::vector<std::pair<FT, FT>>& parameter_space, FT& cluster_epsilon,
                  FT min[2], FT max[2]) const override {
    Base::parameters(indices, parameter_space, cluster_epsilon, min, max);
    // Only touch what is broken: the sphere's own min/max (centred on its
    // equator for wrapping) must stay as CGAL set them.
    for (int k = 0; k < 2; ++k) {
      if (std::isfinite(CGAL::to_double(min[k])) && std::isfinite(CGAL::to_double(max[k]))) {
        bool all_finite = true;
        for (const auto& uv : parameter_space)
          all_finite = all_finite && std::isfinite(CGAL::to_double(k == 0 ? uv.first : uv.second));
        if (all_finite) continue;
      }
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& uv : parameter_space) {
        const double x = CGAL::to_double(k == 0 ? uv.first : uv.second);
        if (std::isfinite(x)) {
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
      }
      if (!(lo <= hi)) lo = hi = 0;  // no finite value at all
      for (auto& uv : parameter_space) {
        FT& x = k == 0 ? uv.first : uv.second;
        if (!std::isfinite(CGAL::to_double(x))) x = FT(lo);
      }
      min[k] = FT(lo);
      max[k] = FT(hi);
    }
    const double ce = CGAL::to_double(cluster_epsilon);
    const double cells = std::ceil(CGAL::to_double(max[0] - min[0]) / ce + 1) *
                         std::ceil(CGAL::to_double(max[1] - min[1]) / ce + 1);
    if (kMayCoarsen && cells > kMaxBitmapCells)
      cluster_epsilon = FT(ce * std::sqrt(cells / kMaxBitmapCells) * 1.01);
  }
};

thread_local double g_min_radius = 0;
thread_local double g_max_radius = std::numeric_limits<double>::infinity();

template <class Base, bool kMayCoarsen>
class RadiusLimited : public SafeBitmap<Base, kMayCoarsen> {
 protected:
  void create_shape(const std::vector<std::size_t>& indices) override {
    Base::create_shape(indices);
    if (!this->m_is_valid) return;
    const double r = CGAL::to_double(this->radius());
    if (!(r >= g_min_radius && r <= g_max_radius)) this->m_is_valid = false;
  }
};
using SafePlane = SafeBitmap<Plane>;
using SafeCone = SafeBitmap<Cone>;
using LimitedCylinder = RadiusLimited<Cylinder, true>;
// Not the sphere: its wrap-around bookkeeping (m_equator) is computed with
// its own cluster_epsilon; its radius limit bounds its bitmap instead.
using LimitedSphere = RadiusLimited<Sphere, false>;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::array<double, 3> to_array(const Kernel::Vector_3& v) {
  return {CGAL::to_double(v.x()), CGAL::to_double(v.y()), CGAL::to_double(v.z())};
}
std::array<double, 3> to_array(const Kernel::Point_3& p) {
  return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
}
std::array<double, 3> unit(std::array<double, 3> v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (n > 0)
    for (double& c : v) c /= n;
  return v;
}

CgalShape empty_shape(CgalShapeType type) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CgalShape s;
  s.type = type;
  s.normal = s.axis = s.point = {nan, nan, nan};
  s.offset = s.radius = s.half_angle_deg = s.major_radius = s.minor_radius = nan;
  return s;
}

}  // namespace

const char* cgal_shape_type_name(CgalShapeType type) {
  switch (type) {
    case CgalShapeType::Plane: return "plane";
    case CgalShapeType::Cylinder: return "cylinder";
    case CgalShapeType::Cone: return "cone";
    case CgalShapeType::Sphere: return "sphere";
    case CgalShapeType::Torus: return "torus";
  }
  return "?";
}

CgalShapeDetectionResult cgal_efficient_ransac(const std::vector<std::array<double, 3>>& points,
                                               const std::vector<std::array<double, 3>>& normals,
                                               const CgalRansacParameters& parameters) {
  CgalShapeDetectionResult result;
  if (points.size() != normals.size()) {
    result.message = "points and normals differ in size";
    return result;
  }
  if (points.empty()) {
    result.message = "no points";
    return result;
  }
  if (!(parameters.planes || parameters.cylinders || parameters.cones || parameters.spheres ||
        parameters.tori)) {
    result.message = "no shape type enabled";
    return result;
  }
  const auto start = Clock::now();

  PointVector input;
  input.reserve(points.size());
  std::array<double, 3> lo = points[0], hi = points[0];
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const auto& n = normals[i];
    input.emplace_back(Kernel::Point_3(p[0], p[1], p[2]), Kernel::Vector_3(n[0], n[1], n[2]), i);
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  result.bbox_diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                   (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                   (hi[2] - lo[2]) * (hi[2] - lo[2]));

  Ransac::Parameters options;
  options.probability = parameters.probability;
  result.min_points = std::max(
      parameters.min_points_at_least,
      static_cast<std::size_t>(std::llround(parameters.min_points_fraction * points.size())));
  options.min_points = result.min_points;
  result.epsilon = options.epsilon = parameters.epsilon_relative * result.bbox_diagonal;
  result.cluster_epsilon = options.cluster_epsilon =
      parameters.cluster_epsilon_relative * result.bbox_diagonal;
  options.normal_threshold = parameters.normal_threshold;

  if (parameters.seed != 0) CGAL::get_default_random() = CGAL::Random(parameters.seed);
  result.max_radius = parameters.max_radius_relative > 0
                          ? parameters.max_radius_relative * result.bbox_diagonal
                          : std::numeric_limits<double>::infinity();
  g_max_radius = result.max_radius;
  g_min_radius = result.epsilon;

  Ransac ransac;
  ransac.set_input(input);
  if (parameters.planes) ransac.add_shape_factory<SafePlane>();
  if (parameters.cylinders) ransac.add_shape_factory<LimitedCylinder>();
  if (parameters.cones) ransac.add_shape_factory<SafeCone>();
  if (parameters.spheres) ransac.add_shape_factory<LimitedSphere>();
  if (parameters.tori) ransac.add_shape_factory<Torus>();

  auto t = Clock::now();
  if (!ransac.preprocess()) {
    result.message = "CGAL preprocess() failed";
    return result;
  }
  result.preprocess_seconds = seconds_since(t);
  t = Clock::now();
  if (!ransac.detect(options)) {
    result.message = "CGAL detect() failed";
    return result;
  }
  result.detect_seconds = seconds_since(t);

  for (const auto& shape : ransac.shapes()) {
    CgalShape s = empty_shape(CgalShapeType::Plane);
    if (const auto* plane = dynamic_cast<const Plane*>(shape.get())) {
      // CGAL's plane: n.x + d = 0 with n = plane_normal() (unit).
      s = empty_shape(CgalShapeType::Plane);
      const Kernel::Vector_3 n = plane->plane_normal();
      const double length = std::sqrt(CGAL::to_double(n.squared_length()));
      s.normal = unit(to_array(n));
      s.offset = -CGAL::to_double(plane->d()) / length;
    } else if (const auto* cylinder = dynamic_cast<const Cylinder*>(shape.get())) {
      s = empty_shape(CgalShapeType::Cylinder);
      const Kernel::Line_3 axis = cylinder->axis();
      s.axis = unit(to_array(axis.to_vector()));
      s.point = to_array(axis.point(0));
      s.radius = CGAL::to_double(cylinder->radius());
    } else if (const auto* cone = dynamic_cast<const Cone*>(shape.get())) {
      s = empty_shape(CgalShapeType::Cone);
      s.axis = unit(to_array(cone->axis()));
      s.point = to_array(cone->apex());
      s.half_angle_deg = CGAL::to_double(cone->angle()) * 180.0 / M_PI;
    } else if (const auto* sphere = dynamic_cast<const Sphere*>(shape.get())) {
      s = empty_shape(CgalShapeType::Sphere);
      s.point = to_array(sphere->center());
      s.radius = CGAL::to_double(sphere->radius());
    } else if (const auto* torus = dynamic_cast<const Torus*>(shape.get())) {
      s = empty_shape(CgalShapeType::Torus);
      s.axis = unit(to_array(torus->axis()));
      s.point = to_array(torus->center());
      s.major_radius = CGAL::to_double(torus->major_radius());
      s.minor_radius = CGAL::to_double(torus->minor_radius());
    } else {
      continue;  // a type we did not register
    }
    const std::vector<std::size_t>& assigned = shape->indices_of_assigned_points();
    s.indices.resize(assigned.size());
    for (std::size_t k = 0; k < assigned.size(); ++k) s.indices[k] = std::get<2>(input[assigned[k]]);
    ++result.count_by_type[static_cast<int>(s.type)];
    result.shapes.push_back(std::move(s));
  }
  result.unassigned_points = ransac.number_of_unassigned_points();
  result.seconds = seconds_since(start);
  result.ok = true;
  return result;
}

}  // namespace bench
}  // namespace femorph
