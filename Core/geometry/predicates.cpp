#include "geometry/predicates.h"

#include <tetgen.h>

// Shewchuk's 2D predicates are compiled into libtet next to the 3D ones but
// tetgen.h does not declare them.
REAL orient2d(REAL* pa, REAL* pb, REAL* pc);
REAL incircle(REAL* pa, REAL* pb, REAL* pc, REAL* pd);

namespace femorph {
namespace {

// exactinit() computes the machine epsilon and error bounds; after that the
// predicates only read globals, so they are safe to call concurrently. It
// runs once when the library is loaded (this file is always linked in with
// the predicates), not on every call: the predicates sit in hot loops.
// Arguments: verbose = 0, noexact = 0 (adaptive exact arithmetic), nofilter
// = 1 (no static filter, which would need a bound on the coordinates); the
// box size is then unused.
const bool exact_arithmetic_ready = (exactinit(0, 0, 1, 1.0, 1.0, 1.0), true);

inline void ensure_exactinit() { (void)exact_arithmetic_ready; }

inline REAL* ptr(const Eigen::Vector3d& p) {
  // Shewchuk's predicates take REAL* but never write through it.
  return const_cast<REAL*>(p.data());
}

inline REAL* ptr(const Eigen::Vector2d& p) { return const_cast<REAL*>(p.data()); }

inline int sign(REAL x) { return (x > 0) - (x < 0); }

}  // namespace

int orient3d_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  ensure_exactinit();
  // Shewchuk's orient3d(a, b, c, d) = (a - d) . ((b - d) x (c - d)), which is
  // minus six times the signed volume in VTK's convention.
  return -sign(orient3d(ptr(a), ptr(b), ptr(c), ptr(d)));
}

int insphere_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                  const Eigen::Vector3d& e) {
  ensure_exactinit();
  // Shewchuk's insphere expects orient3d(a, b, c, d) > 0; swapping a and b
  // turns our positive orientation into his.
  return sign(insphere(ptr(b), ptr(a), ptr(c), ptr(d), ptr(e)));
}

int orient2d_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  ensure_exactinit();
  return sign(orient2d(ptr(a), ptr(b), ptr(c)));
}

int incircle_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d) {
  ensure_exactinit();
  return sign(incircle(ptr(a), ptr(b), ptr(c), ptr(d)));
}

}  // namespace femorph
