// Penetration check of a motion step (bad input: a motion that
// makes objects penetrate is refused, naming the step). Beyond the thesis,
// which assumes a valid motion: each surface vertex of the moving object
// walks through the current mesh to its new position; it may cross space
// and the object's own tets, never the domain's outer boundary nor another
// object.
#include "adapt/adapt.h"

#include "geometry/predicates.h"

#include <random>
#include <sstream>

namespace femorph {

Status detect_penetration(const TetMesh& mesh, const std::vector<int>& material_by_origin, int moving,
                          const std::vector<index_t>& vertices, const std::vector<Vec3>& target) {
  std::vector<index_t> ball;
  std::mt19937 rng(12345);  // the walk's face order: deterministic, no cycles in practice
  const auto describe = [](const Vec3& p) {
    std::ostringstream os;
    os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
    return os.str();
  };
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const index_t v = vertices[i];
    const Vec3& p = target[i];
    mesh.vertex_ball(v, ball);
    if (ball.empty()) continue;
    index_t t = ball[0];
    bool found = false;
    for (int steps = 0; steps < 100000 && !found; ++steps) {
      const Tet& T = mesh.tet(t);
      // The faces p is beyond (negative side), in a random order.
      int beyond[4], n = 0;
      for (int f = 0; f < 4; ++f) {
        const Vec3& a = mesh.point(T[kTetFace[f][0]]);
        const Vec3& b = mesh.point(T[kTetFace[f][1]]);
        const Vec3& c = mesh.point(T[kTetFace[f][2]]);
        // kTetFace's order: the tet's own vertex gives -1, the outside +1.
        if (orient3d_sign(a, b, c, p) > 0) beyond[n++] = f;
      }
      if (n == 0) {
        found = true;
        break;
      }
      const int f = beyond[n == 1 ? 0 : std::uniform_int_distribution<int>(0, n - 1)(rng)];
      const index_t code = mesh.adjacency(t, f);
      if (code < 0) {
        return Status::failure("the moving object would cross the domain's outer boundary (its vertex moving to " +
                               describe(p) + " leaves the mesh)");
      }
      t = code >> 2;
    }
    if (!found) continue;  // undecided: the embedding's checks stay
    const index_t o = mesh.tet_origin(t);
    const int m = o >= 0 && static_cast<std::size_t>(o) < material_by_origin.size() ? material_by_origin[o] : 0;
    if (m != 0 && m != moving)
      return Status::failure("the moving object would penetrate object " + std::to_string(m) + " (its vertex moving to " +
                             describe(p) + " ends inside it)");
  }
  return Status::success();
}

}  // namespace femorph
