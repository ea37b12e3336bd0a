// The mesh before the deformation must be a mesh: its densities (Eq. 2.32)
// and chord errors are the target, and a tet with a repeated point or zero
// volume has an edge of length zero or no shape to measure.
#include "geometry/predicates.h"
#include "improve/improve_target.h"

#include <string>

namespace femorph {

Status check_reference_mesh(const ReferenceMesh& reference) {
  const index_t np = static_cast<index_t>(reference.points.size());
  std::size_t flat = 0, positive = 0, negative = 0;
  index_t first_flat = kInvalidIndex;
  for (std::size_t t = 0; t < reference.tets.size(); ++t) {
    const Tet& T = reference.tets[t];
    for (int i = 0; i < 4; ++i) {
      if (T[i] < 0 || T[i] >= np)
        return Status::failure("tetrahedron " + std::to_string(t) + " refers to point " + std::to_string(T[i]) +
                               ", but there are " + std::to_string(np) + " points");
      for (int j = 0; j < i; ++j)
        if (T[i] == T[j])
          return Status::failure("tetrahedron " + std::to_string(t) + " uses point " + std::to_string(T[i]) +
                                 " twice");
    }
    const int sign = orient3d_sign(reference.points[T[0]], reference.points[T[1]], reference.points[T[2]],
                                   reference.points[T[3]]);
    if (sign == 0 && flat++ == 0) first_flat = static_cast<index_t>(t);
    positive += sign > 0;
    negative += sign < 0;
  }
  if (flat > 0)
    return Status::failure(std::to_string(flat) + (flat == 1 ? " tetrahedron has" : " tetrahedra have") +
                           " zero volume (the first is " + std::to_string(first_flat) + ")");
  if (positive > 0 && negative > 0)
    return Status::failure("its tetrahedra are oriented both ways (" + std::to_string(positive) + " positive, " +
                           std::to_string(negative) + " negative)");
  return Status::success();
}

}  // namespace femorph
