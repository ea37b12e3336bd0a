// A triangulated surface kept as the shape of a boundary region that no
// plane, cylinder, cone, sphere or torus fits (a stretched fillet, a free-form
// face): Improve moves the vertices of such a region on these triangles, the
// input's own, instead of freezing them. Beyond the thesis, which only moves
// vertices of fitted regions (2.6.1.3).
#pragma once

#include "common/types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace femorph {

/// Closest point to p on the triangle (a, b, c), degenerate ones included.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

class DiscreteSurface {
 public:
  /// Copies the triangles (corner positions) and buckets them in a uniform
  /// grid whose cell is about the mean triangle's size.
  void build(std::vector<std::array<Vec3, 3>> triangles);
  bool empty() const { return triangles_.empty(); }
  std::size_t size() const { return triangles_.size(); }
  /// The closest point of the surface to p, searched in growing shells of
  /// grid cells around p; p itself when the surface is empty.
  Vec3 closest_point(const Vec3& p) const;

 private:
  std::vector<std::array<Vec3, 3>> triangles_;
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1;
  std::array<int, 3> dims_{{0, 0, 0}};
  std::vector<std::uint32_t> cell_start_;  // CSR: triangles of cell i
  std::vector<std::uint32_t> cell_items_;

  std::array<int, 3> cell_of(const Vec3& p) const;
};

}  // namespace femorph
