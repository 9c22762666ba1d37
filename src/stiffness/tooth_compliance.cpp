#include "stiffness/tooth_compliance.hpp"

#include "core/error.hpp"

#include <cmath>
#include <numbers>

namespace pw::stiffness {

using geometry::GearKind;
using geometry::GearSpec;
using geometry::Material;

double effective_modulus(const Material& m, ElasticState state) {
  return state == ElasticState::PlaneStrain ? m.youngs_modulus_Pa / (1.0 - m.poisson_ratio * m.poisson_ratio)
                                            : m.youngs_modulus_Pa;
}

FilletCoefficients sainsot_coefficients(double h_f, double theta_f) {
  // Sainsot, Velex & Duverger 2004, Table 1 (columns A_i ... F_i).
  struct Row {
    double A, B, C, D, E, F;
  };
  constexpr Row L{-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045};
  constexpr Row M{60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086};
  constexpr Row P{-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236};
  constexpr Row Q{-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904};
  const auto eval = [&](const Row& r) {
    return r.A / (theta_f * theta_f) + r.B * h_f * h_f + r.C * h_f / theta_f + r.D / theta_f + r.E * h_f + r.F;
  };
  return {eval(L), eval(M), eval(P), eval(Q)};
}

double fillet_compliance(const FilletCoefficients& c, double u_f, double s_f, double alpha_m, double modulus,
                         double width) {
  const double ca = std::cos(alpha_m);
  const double ta = std::tan(alpha_m);
  const double q = u_f / s_f;
  return ca * ca / (modulus * width) * (c.L * q * q + c.M * q + c.P * (1.0 + c.Q * ta * ta));
}

double fillet_half_angle(const GearSpec& s) {
  // Rack frame: the tool tip line (which cuts the root circle) lies h_f* m
  // below the rack reference line, where the gear tooth's half-thickness is
  // pi m/4 + h_f* m tan(a0) at the sharp corner; the tip round of radius
  // rho_f* m meets the tip line rho_f* m tan(pi/4 - a0/2) further out. Rolling
  // the pitch circle (radius m z/2) on the rack maps that abscissa u to the
  // angle u / (m z / 2).
  const double a0 = s.pressure_angle_rad;
  const double u_over_m = std::numbers::pi / 4 + s.dedendum_coef * std::tan(a0) +
                          s.root_fillet_coef * (1.0 - std::sin(a0)) / std::cos(a0);
  return 2.0 * u_over_m / s.teeth;
}

double hertz_compliance(const Material& a, const Material& b, double width) {
  // Yang & Lin 1987: k_h = pi E b / (4 (1 - nu^2)) for equal materials; the
  // two-material form splits 4(1-nu^2)/E into the two bodies' halves.
  return 2.0 / (std::numbers::pi * width) *
         ((1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus_Pa +
          (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus_Pa);
}

ToothModel::ToothModel(const GearSpec& spec, const ToothModelOptions& options)
    : spec_(spec), geo_(geometry::make_geometry(spec)), opt_(options) {
  require(options.quadrature_points >= 2 && options.quadrature_points <= 512, "quadrature_points",
          "must be in [2, 512], got ", options.quadrature_points);
  require(options.shear_factor > 0 && std::isfinite(options.shear_factor), "shear_factor", "must be > 0, got ",
          options.shear_factor);
  require(options.body_ratio > 1.0 && std::isfinite(options.body_ratio), "body_ratio",
          "h_f = r_f / r_int must be > 1 (Sainsot's fit covers [1.4, 7]), got ", options.body_ratio);
  rule_ = gauss_legendre(options.quadrature_points);
  el_.youngs_modulus_Pa = effective_modulus(spec.material, options.elastic_state);
  el_.shear_modulus_Pa = spec.material.shear_modulus_Pa;
  el_.shear_factor = options.shear_factor;
  el_.face_width_m = spec.face_width_m;
  theta_f_ = fillet_half_angle(spec);
  fillet_ = sainsot_coefficients(options.body_ratio, theta_f_);
  internal_ = spec.kind == GearKind::Internal;

  const double rb = geo_.base_radius_m;
  const double rf = geo_.root_radius_m;
  if (internal_) {
    r_beam_root_ = rf;
    x_root_ = rf * std::cos(geometry::half_tooth_angle_at(spec_, geo_, rf));
  } else if (rf < rb) {
    // The flank below the base circle: the radial line through the involute's
    // start (its tangent there), at polar angle theta_b from the centreline.
    straight_segment_ = options.include_root_segment;
    r_beam_root_ = straight_segment_ ? rf : rb;
    x_root_ = r_beam_root_ * std::cos(geo_.half_base_tooth_angle_rad);
  } else {
    r_beam_root_ = rf;
    x_root_ = rf * std::cos(geometry::half_tooth_angle_at(spec_, geo_, rf));
  }
}

ToothLoad ToothModel::load_at(double r) const {
  ToothLoad L;
  L.pressure_angle_rad = geometry::pressure_angle_at(geo_, r);
  L.half_angle_rad = geometry::half_tooth_angle_at(spec_, geo_, r);
  const double xc = r * std::cos(L.half_angle_rad);
  const double hc = r * std::sin(L.half_angle_rad);
  const double rf = geo_.root_radius_m;
  L.beam.offset_m = hc;
  if (internal_) {
    // Ring tooth: the force on the flank points along (sin phi, -cos phi) with
    // phi = theta + alpha the polar angle of the base-circle tangent point, so
    // its component along the centreline points outwards, to the root.
    L.beam.angle_rad = L.pressure_angle_rad + L.half_angle_rad;
    L.beam.lever_m = x_root_ - xc;
    L.u_f_m = rf - (xc + hc * std::tan(L.beam.angle_rad));
  } else {
    // External tooth (Tian 2004): alpha1 = alpha_r - theta_r.
    L.beam.angle_rad = L.pressure_angle_rad - L.half_angle_rad;
    L.beam.lever_m = xc - x_root_;
    L.u_f_m = xc - hc * std::tan(L.beam.angle_rad) - rf;
  }
  return L;
}

ToothCompliance ToothModel::compliance(double r) const {
  const double rb = geo_.base_radius_m;
  const double ra = geo_.tip_radius_m;
  const double rf = geo_.root_radius_m;
  const double tol = 1e-12 * ra;
  if (internal_) {
    require(r >= ra - tol && r <= rf + tol, "contact_radius_m", "ring contact radius ", r,
            " m must lie on the flank [r_a, r_f] = [", ra, ", ", rf, "] m");
  } else {
    const double lo = std::fmax(rb, rf);
    require(r >= lo - tol && r <= ra + tol, "contact_radius_m", "contact radius ", r,
            " m must lie on the involute [max(r_b, r_f), r_a] = [", lo, ", ", ra, "] m");
  }
  r = internal_ ? std::fmin(std::fmax(r, ra), rf) : std::fmin(std::fmax(r, std::fmax(rb, rf)), ra);

  const ToothLoad load = load_at(r);
  const double theta_b = geo_.half_base_tooth_angle_rad;
  const auto roll = [&](double radius) { return std::sqrt(std::fmax(0.0, (radius / rb) * (radius / rb) - 1.0)); };
  ToothCompliance c;

  if (internal_) {
    // theta(t) = theta_b + inv(alpha) = theta_b + t - atan t, r(t) = r_b sqrt(1 + t^2);
    // s = x_root - r cos(theta) grows towards the tip.
    const auto section = [&](double t) {
      const double q = std::sqrt(1.0 + t * t);
      const double th = theta_b + t - std::atan(t);
      const double rr = rb * q;
      BeamSection s;
      s.s_m = x_root_ - rr * std::cos(th);
      s.half_thickness_m = rr * std::sin(th);
      s.ds_dt = -(rb * t / q) * (std::cos(th) - t * std::sin(th));
      return s;
    };
    c += beam_compliance(section, roll(r), roll(rf), load.beam, el_, rule_);
  } else {
    if (straight_segment_) {
      const double cb = std::cos(theta_b), sb = std::sin(theta_b);
      const auto line = [&](double rr) {
        BeamSection s;
        s.s_m = rr * cb - x_root_;
        s.half_thickness_m = rr * sb;
        s.ds_dt = cb;
        return s;
      };
      c += beam_compliance(line, rf, rb, load.beam, el_, rule_);
    }
    // theta(t) = theta_b - inv(alpha) = theta_b - t + atan t; the roll angle
    // t makes the integrand analytic (no sqrt(r - r_b) at the base circle).
    const auto section = [&](double t) {
      const double q = std::sqrt(1.0 + t * t);
      const double th = theta_b - t + std::atan(t);
      const double rr = rb * q;
      BeamSection s;
      s.s_m = rr * std::cos(th) - x_root_;
      s.half_thickness_m = rr * std::sin(th);
      s.ds_dt = (rb * t / q) * (std::cos(th) + t * std::sin(th));
      return s;
    };
    c += beam_compliance(section, roll(r_beam_root_), roll(r), load.beam, el_, rule_);
  }

  if (opt_.include_fillet_foundation) {
    c.fillet_m_N = fillet_compliance(fillet_, load.u_f_m, 2.0 * rf * theta_f_, load.beam.angle_rad,
                                     el_.youngs_modulus_Pa, el_.face_width_m);
  }
  return c;
}

ToothCompliance tooth_compliance(const GearSpec& spec, double r, const ToothModelOptions& options) {
  return ToothModel(spec, options).compliance(r);
}

} // namespace pw::stiffness
