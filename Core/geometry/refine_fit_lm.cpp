#include "geometry/fit_internal.h"

#include <Eigen/Cholesky>

namespace femorph {

namespace {

// Each model holds the control variables of Fig. 2.16 in normalised
// coordinates (points centred and scaled to unit rms radius). A step is taken
// in local increments that are minimal (an axis turns by two angles about
// itself, a point on an axis moves across it), so the normal equations are
// regular; after the step the variables are normalised as in Fig. 2.16.
// row(): the residual d_i (Eq. 2.8) and its derivatives by the increments.

// Unit u, v completing a to a right-handed frame.
void frame_of(const Vec3& a, Vec3& u, Vec3& v) {
  u = a.unitOrthogonal();
  v = a.cross(u);
}

// Derivatives of f (distance to the axis) and g (height along it) of a point,
// for an axis through q along a: by moving q along u, v and by turning a
// towards u, v.
struct AxisTerms {
  double f, g;
  double df_qu, df_qv;  // dg_qu = dg_qv = 0, dg_q(along a) = -1
  double df_au, df_av, dg_au, dg_av;
};

AxisTerms axis_terms(const Vec3& y, const Vec3& q, const Vec3& a, const Vec3& u, const Vec3& v) {
  AxisTerms t;
  const Vec3 w = y - q;
  t.g = w.dot(a);
  const Vec3 radial = w - t.g * a;
  t.f = radial.norm();
  const Vec3 e = t.f > 0 ? Vec3(radial / t.f) : u;
  const double eu = e.dot(u), ev = e.dot(v);
  t.df_qu = -eu;
  t.df_qv = -ev;
  t.df_au = -t.g * eu;
  t.df_av = -t.g * ev;
  t.dg_au = t.f * eu;
  t.dg_av = t.f * ev;
  return t;
}

Vec3 turned(const Vec3& a, const Vec3& u, const Vec3& v, double du, double dv) {
  return (a + du * u + dv * v).normalized();
}

struct PlaneModel {
  static constexpr int kParams = 3;  // normal turn (2), offset along the normal
  Vec3 q, a, u, v;
  explicit PlaneModel(const SurfacePrimitive& s) : q(s.point), a(s.axis.normalized()) { normalise(); }
  void normalise() {
    q = a * a.dot(q);  // the plane point closest to the (normalised) origin
    frame_of(a, u, v);
  }
  bool valid() const { return q.allFinite() && a.allFinite() && a.norm() > 0.5; }
  double residual(const Vec3& y) const { return (y - q).dot(a); }
  double row(const Vec3& y, double* j) const {
    const Vec3 w = y - q;
    j[0] = w.dot(u);
    j[1] = w.dot(v);
    j[2] = -1;
    return w.dot(a);
  }
  PlaneModel step(const double* d) const {
    PlaneModel m = *this;
    m.q = q + d[2] * a;
    m.a = turned(a, u, v, d[0], d[1]);
    m.normalise();
    return m;
  }
  SurfacePrimitive surface() const {
    SurfacePrimitive s;
    s.type = SurfaceType::Plane;
    s.point = q;
    s.axis = a;
    return s;
  }
};

struct CylinderModel {
  static constexpr int kParams = 5;  // axis point across the axis (2), axis turn (2), radius
  Vec3 q, a, u, v;
  double radius;
  explicit CylinderModel(const SurfacePrimitive& s) : q(s.point), a(s.axis.normalized()), radius(s.radius) {
    normalise();
  }
  void normalise() {
    q -= a * a.dot(q);  // the axis point closest to the origin
    frame_of(a, u, v);
  }
  bool valid() const { return q.allFinite() && a.allFinite() && a.norm() > 0.5 && radius > 0; }
  double residual(const Vec3& y) const {
    const Vec3 w = y - q;
    return (w - w.dot(a) * a).norm() - radius;
  }
  double row(const Vec3& y, double* j) const {
    const AxisTerms t = axis_terms(y, q, a, u, v);
    j[0] = t.df_qu;
    j[1] = t.df_qv;
    j[2] = t.df_au;
    j[3] = t.df_av;
    j[4] = -1;
    return t.f - radius;
  }
  CylinderModel step(const double* d) const {
    CylinderModel m = *this;
    m.q = q + d[0] * u + d[1] * v;
    m.a = turned(a, u, v, d[2], d[3]);
    m.radius = radius + d[4];
    m.normalise();
    return m;
  }
  SurfacePrimitive surface() const {
    SurfacePrimitive s;
    s.type = SurfaceType::Cylinder;
    s.point = q;
    s.axis = a;
    s.radius = radius;
    return s;
  }
};

// Fig. 2.16(a): q on the axis, a from q towards the apex, s the orthogonal
// distance from q to the cone, phi the half angle;
// d = f cos(phi) + g sin(phi) - s. Unlike the apex, (q, s, phi) stay well
// conditioned for slender cones.
struct ConeModel {
  static constexpr int kParams = 6;  // q across the axis (2), axis turn (2), s, phi
  Vec3 q, a, u, v;
  double s, phi;
  double cos_phi = 1, sin_phi = 0;  // cached: one sincos per step, not per point
  explicit ConeModel(const SurfacePrimitive& c) {
    a = -c.axis.normalized();  // towards the apex
    phi = c.half_angle;
    q = c.point - a * a.dot(c.point);            // the axis point closest to the origin
    s = std::sin(phi) * (c.point - q).dot(a);  // the apex is at g = s / sin(phi)
    normalise();
  }
  void normalise() {
    // Fig. 2.16 normalisations, written so that the surface is unchanged:
    // q back to the axis point closest to the origin (g shifts, so s does);
    // phi into [0, pi/2] by turning a (and s) over.
    const double t = q.dot(a);
    q -= t * a;
    s += t * std::sin(phi);
    phi = std::remainder(phi, 2 * kPi);
    if (phi < 0) {
      phi = -phi;
      a = -a;
    }
    if (phi > kPi / 2) {
      phi = kPi - phi;
      a = -a;
      s = -s;
    }
    frame_of(a, u, v);
    cos_phi = std::cos(phi);
    sin_phi = std::sin(phi);
  }
  bool valid() const {
    return q.allFinite() && a.allFinite() && a.norm() > 0.5 && std::isfinite(s) && phi > 0 && phi < kPi / 2;
  }
  double residual(const Vec3& y) const {
    const Vec3 w = y - q;
    const double g = w.dot(a);
    return (w - g * a).norm() * cos_phi + g * sin_phi - s;
  }
  double row(const Vec3& y, double* j) const {
    const AxisTerms t = axis_terms(y, q, a, u, v);
    const double c = cos_phi, sn = sin_phi;
    j[0] = c * t.df_qu;
    j[1] = c * t.df_qv;
    j[2] = c * t.df_au + sn * t.dg_au;
    j[3] = c * t.df_av + sn * t.dg_av;
    j[4] = -1;
    j[5] = -t.f * sn + t.g * c;
    return t.f * c + t.g * sn - s;
  }
  ConeModel step(const double* d) const {
    ConeModel m = *this;
    m.q = q + d[0] * u + d[1] * v;
    m.a = turned(a, u, v, d[2], d[3]);
    m.s = s + d[4];
    m.phi = phi + d[5];
    m.normalise();
    return m;
  }
  SurfacePrimitive surface() const {
    SurfacePrimitive c;
    c.type = SurfaceType::Cone;
    c.point = q + a * (s / std::sin(phi));
    c.axis = -a;
    c.half_angle = phi;
    return c;
  }
};

// Fig. 2.16(b): d = |x - q| - r; no normalisation.
struct SphereModel {
  static constexpr int kParams = 4;
  Vec3 q;
  double radius;
  explicit SphereModel(const SurfacePrimitive& s) : q(s.point), radius(s.radius) {}
  bool valid() const { return q.allFinite() && radius > 0; }
  double residual(const Vec3& y) const { return (y - q).norm() - radius; }
  double row(const Vec3& y, double* j) const {
    const Vec3 w = y - q;
    const double l = w.norm();
    const Vec3 e = l > 0 ? Vec3(w / l) : Vec3::UnitX();
    j[0] = -e.x();
    j[1] = -e.y();
    j[2] = -e.z();
    j[3] = -1;
    return l - radius;
  }
  SphereModel step(const double* d) const {
    SphereModel m = *this;
    m.q += Vec3(d[0], d[1], d[2]);
    m.radius += d[3];
    return m;
  }
  SurfacePrimitive surface() const {
    SurfacePrimitive s;
    s.type = SurfaceType::Sphere;
    s.point = q;
    s.radius = radius;
    return s;
  }
};

// Fig. 2.16(c): d = sqrt(g^2 + (f - R)^2) - r; a normalised.
struct TorusModel {
  static constexpr int kParams = 7;  // centre (3: across, across, along), axis turn (2), R, r
  Vec3 q, a, u, v;
  double major, minor;
  explicit TorusModel(const SurfacePrimitive& s)
      : q(s.point), a(s.axis.normalized()), major(s.radius), minor(s.minor_radius) {
    frame_of(a, u, v);
  }
  bool valid() const { return q.allFinite() && a.allFinite() && a.norm() > 0.5 && major >= 0 && minor > 0; }
  double residual(const Vec3& y) const {
    const Vec3 w = y - q;
    const double g = w.dot(a);
    const double f = (w - g * a).norm() - major;
    return std::sqrt(f * f + g * g) - minor;  // not hypot: slow, and no overflow here
  }
  double row(const Vec3& y, double* j) const {
    const AxisTerms t = axis_terms(y, q, a, u, v);
    const double fr = t.f - major;
    const double D = std::sqrt(fr * fr + t.g * t.g);
    // On the core circle the distance has no derivative; such a point carries
    // no information about the position of the tube.
    const double cf = D > 0 ? fr / D : 0, cg = D > 0 ? t.g / D : 0;
    j[0] = cf * t.df_qu;
    j[1] = cf * t.df_qv;
    j[2] = -cg;
    j[3] = cf * t.df_au + cg * t.dg_au;
    j[4] = cf * t.df_av + cg * t.dg_av;
    j[5] = -cf;
    j[6] = -1;
    return D - minor;
  }
  TorusModel step(const double* d) const {
    TorusModel m = *this;
    m.q = q + d[0] * u + d[1] * v + d[2] * a;
    m.a = turned(a, u, v, d[3], d[4]);
    m.major = major + d[5];
    m.minor = minor + d[6];
    frame_of(m.a, m.u, m.v);
    return m;
  }
  SurfacePrimitive surface() const {
    SurfacePrimitive s;
    s.type = SurfaceType::Torus;
    s.point = q;
    s.axis = a;
    s.radius = major;
    s.minor_radius = minor;
    return s;
  }
};

template <class Model>
double cost_of(const Model& m, const std::vector<Vec3>& y) {
  double sum = 0;
  for (const Vec3& p : y) {
    const double r = m.residual(p);
    sum += r * r;
  }
  return sum;
}

// Levenberg-Marquardt as in Fig. 2.15: lambda starts at 1e-4, the damped
// normal equations (J^T J + lambda diag(J^T J)) delta = -J^T d; a step that
// lowers J_LM is taken and lambda divided by 10, else lambda is multiplied by
// 10 and the step retried. Stops when J_LM no longer decreases by the
// relative `tolerance`, when the step is below rounding, or after
// max_iterations Jacobians. Returns false if the model became invalid.
template <class Model>
bool levenberg_marquardt(Model& model, const std::vector<Vec3>& y, const LmParams& params, int& iterations,
                         double& initial_cost, double& final_cost) {
  constexpr int P = Model::kParams;
  using Matrix = Eigen::Matrix<double, P, P>;
  using Vector = Eigen::Matrix<double, P, 1>;
  constexpr double kInitialLambda = 1e-4;
  constexpr double kMaxLambda = 1e16;
  // Parameters are O(1) in normalised coordinates: smaller steps are rounding.
  constexpr double kStepFloor = 1e-14;

  double cost = cost_of(model, y);
  initial_cost = final_cost = cost;
  iterations = 0;
  if (!std::isfinite(cost)) return false;
  double lambda = kInitialLambda;
  double row[P];
  // Points are centred and scaled to unit size: residuals of 1e-14 are
  // rounding, and iterating further only chases it (exact CAD meshes reach
  // this in a few steps).
  const double rounding_floor = static_cast<double>(y.size()) * 1e-28;
  while (iterations < params.max_iterations && cost > rounding_floor) {
    ++iterations;
    Matrix H = Matrix::Zero();
    Vector g = Vector::Zero();
    for (const Vec3& p : y) {
      const double r = model.row(p, row);
      const Eigen::Map<const Vector> j(row);
      H.noalias() += j * j.transpose();
      g += r * j;
    }
    Vector scaling = H.diagonal().cwiseMax(1e-12 * std::max(H.diagonal().maxCoeff(), 1e-300));
    bool accepted = false, converged = false;
    while (lambda <= kMaxLambda) {
      Matrix damped = H;
      damped.diagonal() += lambda * scaling;
      const Vector delta = -damped.ldlt().solve(g);
      if (!delta.allFinite()) {
        lambda *= 10;
        continue;
      }
      const Model trial = model.step(delta.data());
      const double trial_cost = trial.valid() ? cost_of(trial, y) : std::numeric_limits<double>::infinity();
      if (trial_cost < cost) {
        const double decrease = (cost - trial_cost) / cost;
        model = trial;
        cost = trial_cost;
        lambda = std::max(lambda / 10, 1e-12);
        accepted = true;
        converged = decrease < params.tolerance || delta.template lpNorm<Eigen::Infinity>() < kStepFloor;
        break;
      }
      // No decrease from a step below rounding: at the minimum.
      if (delta.template lpNorm<Eigen::Infinity>() < kStepFloor) {
        converged = true;
        break;
      }
      lambda *= 10;
    }
    if (!accepted || converged) break;
  }
  final_cost = cost;
  return model.valid();
}

template <class Model>
FitResult refine(const SurfacePrimitive& initial, const std::vector<Vec3>& points, const LmParams& params) {
  const auto refused = [&] {
    FitResult result = evaluate_fit(initial, points);
    result.ok = false;
    return result;
  };
  if (static_cast<int>(points.size()) < Model::kParams) return refused();
  const detail::Normalisation frame(points);
  if (!frame.valid()) return refused();
  const std::vector<Vec3> y = frame.apply(points);
  Model model(frame.to_unit(initial));
  if (!model.valid()) return refused();
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
  if (!levenberg_marquardt(model, y, params, iterations, initial_cost, final_cost)) return refused();
  FitResult refined = evaluate_fit(frame.to_world(model.surface()), points);
  if (!refined.ok || !detail::finite_surface(refined.surface)) return refused();
  refined.iterations = iterations;
  return refined;
}

}  // namespace

FitResult refine_fit_lm(const SurfacePrimitive& initial, const std::vector<Vec3>& points, const LmParams& params) {
  switch (initial.type) {
    case SurfaceType::Plane: return refine<PlaneModel>(initial, points, params);
    case SurfaceType::Cylinder: return refine<CylinderModel>(initial, points, params);
    case SurfaceType::Cone: return refine<ConeModel>(initial, points, params);
    case SurfaceType::Sphere: return refine<SphereModel>(initial, points, params);
    case SurfaceType::Torus: return refine<TorusModel>(initial, points, params);
    case SurfaceType::Unknown: break;
  }
  FitResult result;
  result.surface = initial;
  return result;
}

}  // namespace femorph
