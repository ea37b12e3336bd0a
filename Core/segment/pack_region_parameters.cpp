// The fixed-width rows of the RegionParameters and CurveParameters field
// arrays (docs/ARCHITECTURE.md), so the fits the Segment filter writes reach
// Improve (and Deform) through .vtu files and ParaView pipelines. Layouts:
// segmentation.h.
#include "segment/segmentation.h"

#include <cmath>

namespace femorph {
namespace {

template <std::size_t N>
void put(std::array<double, N>& row, int at, const Vec3& v) {
  row[at] = v.x();
  row[at + 1] = v.y();
  row[at + 2] = v.z();
}

Vec3 get(const double* row, int at) { return Vec3(row[at], row[at + 1], row[at + 2]); }

// Region and curve ids are stored as doubles (exact up to 2^53).
double id_value(index_t id) { return static_cast<double>(id); }

}  // namespace

std::array<double, kRegionParameterWidth> pack_region_parameters(const Region& region) {
  std::array<double, kRegionParameterWidth> row{};
  const SurfacePrimitive& s = region.surface;
  put(row, 0, s.point);
  put(row, 3, s.axis);
  row[6] = s.radius;
  row[7] = s.minor_radius;
  row[8] = s.half_angle;
  row[9] = static_cast<double>(static_cast<std::int32_t>(region.convexity));
  row[10] = region.fit_rms;
  row[11] = region.area;
  return row;
}

SurfacePrimitive unpack_region_surface(SurfaceType type, const double* row) {
  SurfacePrimitive s;
  s.type = type;
  if (!row) return s;
  s.point = get(row, 0);
  s.axis = get(row, 3);
  s.radius = row[6];
  s.minor_radius = row[7];
  s.half_angle = row[8];
  return s;
}

std::array<double, kCurveParameterWidth> pack_curve_parameters(const BoundaryCurve& curve) {
  std::array<double, kCurveParameterWidth> row{};
  const CurvePrimitive& c = curve.curve;
  put(row, 0, c.center);
  put(row, 3, c.normal);
  put(row, 6, c.direction);
  row[9] = c.radius;
  row[10] = c.minor_radius;
  put(row, 11, c.start);
  put(row, 14, c.end);
  row[17] = id_value(curve.region_a);
  row[18] = id_value(curve.region_b);
  row[19] = static_cast<double>(static_cast<std::int32_t>(curve.continuity));
  return row;
}

BoundaryCurve unpack_curve_parameters(CurveType type, const double* row) {
  BoundaryCurve curve;
  curve.type = type;
  curve.curve.type = type;
  if (!row) return curve;
  CurvePrimitive& c = curve.curve;
  c.center = get(row, 0);
  c.normal = get(row, 3);
  c.direction = get(row, 6);
  c.radius = row[9];
  c.minor_radius = row[10];
  c.start = get(row, 11);
  c.end = get(row, 14);
  curve.region_a = static_cast<index_t>(std::lround(row[17]));
  curve.region_b = static_cast<index_t>(std::lround(row[18]));
  curve.continuity = std::lround(row[19]) == 1 ? Continuity::G1 : Continuity::G0;
  return curve;
}

}  // namespace femorph
