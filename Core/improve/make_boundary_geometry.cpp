// The fitted surfaces and curves Improve keeps boundary vertices on, from a
// segmentation as FEMorph Segment's arrays carry it (thesis 2.5.1.1).
#include "improve/boundary_geometry.h"
#include "segment/segmentation.h"

namespace femorph {

BoundaryGeometry make_boundary_geometry(const std::vector<SurfacePrimitive>& regions,
                                        const std::vector<BoundaryCurve>& curves) {
  BoundaryGeometry g;
  g.regions = regions;
  g.curves.reserve(curves.size());
  g.curve_regions.reserve(curves.size());
  for (const BoundaryCurve& c : curves) {
    g.curves.push_back(c.curve);
    g.curves.back().type = c.type;
    g.curve_regions.push_back({c.region_a, c.region_b});
  }
  return g;
}

}  // namespace femorph
