#include "geometry/gear.hpp"

#include "core/error.hpp"

#include <cmath>
#include <numbers>

namespace pw::geometry {

double involute(double alpha_rad) { return std::tan(alpha_rad) - alpha_rad; }

double inverse_involute(double inv_alpha) {
  // Newton on f(a) = tan a - a - inv, f'(a) = tan^2 a, from Cheng's guess,
  // safeguarded by bisection on the bracket [lo, hi] of (0, pi/2): f is
  // increasing and convex there, so a Newton step that leaves the bracket
  // is replaced by the midpoint (without it Newton overshoots past pi/2 for
  // angles above ~1.28 rad).
  if (inv_alpha <= 0.0) return 0.0;
  double lo = 0.0, hi = 0.5 * std::numbers::pi;
  double a = std::fmin(std::cbrt(3.0 * inv_alpha) - 0.4 * inv_alpha, 1.5);
  if (!(a > lo && a < hi)) a = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double t = std::tan(a);
    const double f = t - a - inv_alpha;
    if (f > 0) hi = a; else lo = a;
    double next = a - f / (t * t);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - a) < 1e-15 * std::fmax(1.0, a)) return next;
    a = next;
  }
  return a;
}

GearGeometry make_geometry(const GearSpec& s) {
  require(s.teeth >= 3, "teeth", "must be >= 3, got ", s.teeth);
  require(s.module_m > 0 && std::isfinite(s.module_m), "module_m", "must be > 0 [m], got ", s.module_m);
  require(s.pressure_angle_rad > 0 && s.pressure_angle_rad <= std::numbers::pi / 4, "pressure_angle_rad",
          "must be in (0, pi/4] rad, got ", s.pressure_angle_rad);
  require(std::isfinite(s.profile_shift) && std::fabs(s.profile_shift) <= 1.5, "profile_shift",
          "must be in [-1.5, 1.5], got ", s.profile_shift);
  require(s.addendum_coef > 0 && s.addendum_coef <= 2, "addendum_coef", "must be in (0, 2], got ", s.addendum_coef);
  require(s.dedendum_coef > s.addendum_coef && s.dedendum_coef <= 2.5, "dedendum_coef",
          "must be in (addendum_coef, 2.5], got ", s.dedendum_coef);
  require(s.root_fillet_coef >= 0 && s.root_fillet_coef <= 0.5, "root_fillet_coef", "must be in [0, 0.5], got ",
          s.root_fillet_coef);
  require(s.face_width_m > 0 && std::isfinite(s.face_width_m), "face_width_m", "must be > 0 [m], got ",
          s.face_width_m);
  const Material& mat = s.material;
  require(mat.youngs_modulus_Pa > 0 && std::isfinite(mat.youngs_modulus_Pa), "youngs_modulus_Pa",
          "must be > 0 [Pa], got ", mat.youngs_modulus_Pa);
  require(mat.shear_modulus_Pa > 0 && std::isfinite(mat.shear_modulus_Pa), "shear_modulus_Pa",
          "must be > 0 [Pa], got ", mat.shear_modulus_Pa);
  require(mat.poisson_ratio > -1 && mat.poisson_ratio < 0.5, "poisson_ratio", "must be in (-1, 0.5), got ",
          mat.poisson_ratio);
  require(mat.density_kg_m3 > 0 && std::isfinite(mat.density_kg_m3), "density_kg_m3",
          "must be > 0 [kg/m^3], got ", mat.density_kg_m3);

  GearGeometry g;
  const double m = s.module_m;
  const double z = s.teeth;
  const double a0 = s.pressure_angle_rad;
  g.reference_radius_m = 0.5 * m * z;
  g.base_radius_m = g.reference_radius_m * std::cos(a0);
  g.base_pitch_m = std::numbers::pi * m * std::cos(a0);
  if (s.kind == GearKind::External) {
    g.tip_radius_m = g.reference_radius_m + m * (s.addendum_coef + s.profile_shift);
    g.root_radius_m = g.reference_radius_m - m * (s.dedendum_coef - s.profile_shift);
    g.half_base_tooth_angle_rad = std::numbers::pi / (2 * z) + 2 * s.profile_shift * std::tan(a0) / z + involute(a0);
  } else {
    g.tip_radius_m = g.reference_radius_m - m * (s.addendum_coef - s.profile_shift);
    g.root_radius_m = g.reference_radius_m + m * (s.dedendum_coef + s.profile_shift);
    // Ring tooth: bounded by the involutes of the base circle on its concave
    // side, so its angular half-thickness grows with radius.
    g.half_base_tooth_angle_rad = std::numbers::pi / (2 * z) - 2 * s.profile_shift * std::tan(a0) / z - involute(a0);
  }
  require(g.root_radius_m > 0, "dedendum_coef", "root circle radius ", g.root_radius_m, " m is not positive");
  if (s.kind == GearKind::External) {
    require(half_tooth_angle_at(s, g, g.tip_radius_m) > 0, "addendum_coef",
            "tooth comes to a point below the tip circle (r_a = ", g.tip_radius_m, " m); reduce addendum or shift");
  } else {
    require(g.tip_radius_m > g.base_radius_m, "addendum_coef",
            "internal gear tip circle r_a = ", g.tip_radius_m, " m must lie outside its base circle r_b = ",
            g.base_radius_m, " m (involute undefined inside the base circle)");
  }
  return g;
}

double pressure_angle_at(const GearGeometry& g, double r) { return std::acos(std::fmin(1.0, g.base_radius_m / r)); }

double half_tooth_angle_at(const GearSpec& s, const GearGeometry& g, double r) {
  const double z = s.teeth;
  const double a0 = s.pressure_angle_rad;
  const double ar = pressure_angle_at(g, r);
  if (s.kind == GearKind::External)
    return std::numbers::pi / (2 * z) + 2 * s.profile_shift * std::tan(a0) / z + involute(a0) - involute(ar);
  return std::numbers::pi / (2 * z) - 2 * s.profile_shift * std::tan(a0) / z - involute(a0) + involute(ar);
}

double roll_angle_at(const GearGeometry& g, double r) {
  const double q = r / g.base_radius_m;
  return std::sqrt(std::fmax(0.0, q * q - 1.0));
}

} // namespace pw::geometry
