#include "geometry/curve_primitive.h"

namespace femorph {

const char* to_string(CurveType type) {
  switch (type) {
    case CurveType::Line: return "line";
    case CurveType::Circle: return "circle";
    case CurveType::CircularArc: return "circular arc";
    case CurveType::Ellipse: return "ellipse";
    case CurveType::EllipticArc: return "elliptic arc";
    case CurveType::Parabola: return "parabola";
    case CurveType::Hyperbola: return "hyperbola";
    case CurveType::Unclassified: break;
  }
  return "unclassified";
}

}  // namespace femorph
