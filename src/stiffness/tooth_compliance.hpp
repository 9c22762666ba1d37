// Compliance of ONE spur-gear tooth under a unit normal force applied along
// the line of action at a contact point of radius r: the potential-energy
// (PE) method of Yang & Lin (1987) and Tian (2004) as summarised by Wu, Zuo &
// Parey (2008), with the gear-body ("fillet foundation") term of Sainsot,
// Velex & Duverger (2004). docs/stiffness.md §1 derives every formula here.
//
// The tooth is a cantilever of variable section clamped at its root. With s
// the distance from the root section along the tooth centreline, h(s) the
// half-thickness, b the face width, and the load at (s = d, offset h_c) making
// the angle alpha1 with the normal to the centreline, the strain energies of
// a force F are (Tian 2004, chapter 2; Wu et al. 2008, section 2)
//   U_b = int_0^d [F cos(a1) (d - s) - F sin(a1) h_c]^2 / (2 E I(s)) ds,  I = (2h)^3 b / 12
//   U_s = int_0^d 1.2 F^2 cos^2(a1) / (2 G A(s)) ds,                     A = 2 h b
//   U_a = int_0^d F^2 sin^2(a1) / (2 E A(s)) ds
// and each compliance is c = 2U / F^2 [m/N], the displacement of the load
// point along the force per unit force.
//
// Conventions: SI units; a positive sin(alpha1) compresses the tooth (the
// axial component points towards the root). External teeth are clamped at the
// root circle r_f; when r_f < r_b the flank between root and base circle is
// the radial line that continues the involute's tangent at r_b (the
// "straight segment" of Liang, Zuo & Pandey 2014 and Ma et al. 2015). Ring
// (internal) teeth point towards the axis and are clamped at their root
// circle, the largest radius of the tooth; their flank is the involute of the
// ring's base circle all the way to the root (Chen & Shao 2013 use the same
// beam integral with the internal tooth's section).
#pragma once

#include "geometry/gear.hpp"
#include "stiffness/quadrature.hpp"

#include <cmath>

namespace pw::stiffness {

/// Which elastic constant the beam and body terms use. A spur tooth whose face
/// width b is large against its thickness deforms in plane strain, with the
/// effective modulus E / (1 - nu^2) (Cornell 1981; Weber & Banaschek 1953,
/// the basis of ISO 6336-1's c'_th); narrow teeth are in plane stress (E).
/// See docs/stiffness.md §1.4 for the choice of default.
enum class ElasticState { PlaneStress, PlaneStrain };

/// E for PlaneStress, E / (1 - nu^2) for PlaneStrain [Pa].
double effective_modulus(const geometry::Material& material, ElasticState state);

/// Compliance parts of one tooth [m/N], each for a unit force along the
/// line of action, measured along it.
struct ToothCompliance {
  double bending_m_N = 0;
  double shear_m_N = 0;
  double axial_m_N = 0;
  double fillet_m_N = 0;  ///< Sainsot et al. 2004 gear-body term (0 if excluded)
  double total_m_N() const { return bending_m_N + shear_m_N + axial_m_N + fillet_m_N; }
  ToothCompliance& operator+=(const ToothCompliance& o) {
    bending_m_N += o.bending_m_N;
    shear_m_N += o.shear_m_N;
    axial_m_N += o.axial_m_N;
    fillet_m_N += o.fillet_m_N;
    return *this;
  }
};

/// The load on a cantilever, in the beam's own frame.
struct BeamLoad {
  double lever_m = 0;    ///< d: distance of the load point's section from the root section, along the centreline [m]
  double offset_m = 0;   ///< h_c: distance of the load point from the centreline [m]
  double angle_rad = 0;  ///< alpha1: angle between the force and the normal to the centreline [rad]
};

/// Elastic constants of a beam and its width.
struct BeamElasticity {
  double youngs_modulus_Pa = 0;  ///< E, or E/(1-nu^2) in plane strain
  double shear_modulus_Pa = 0;   ///< G
  double shear_factor = 1.2;     ///< kappa in U_s (1.2: rectangular section, Tian 2004)
  double face_width_m = 0;       ///< b
};

/// One point of a beam description at parameter t: its distance s from the
/// root along the centreline, its half-thickness h and ds/dt.
struct BeamSection {
  double s_m = 0;
  double half_thickness_m = 0;
  double ds_dt = 0;
};

/// Beam-energy compliance (bending, shear, axial; fillet left 0) of the part
/// of a cantilever described by `section_at(t)` for t between t0 and t1 (either
/// order; the part must lie between the root and the load point), integrated
/// with `rule`. This is the general integral of the header comment; any
/// section law can be passed (tests use a uniform beam).
template <class SectionAt>
ToothCompliance beam_compliance(const SectionAt& section_at, double t0, double t1, const BeamLoad& load,
                                const BeamElasticity& el, const GaussLegendreRule& rule) {
  const double ca = std::cos(load.angle_rad);
  const double sa = std::sin(load.angle_rad);
  const double b = el.face_width_m;
  ToothCompliance c;
  const double half = 0.5 * (t1 - t0);
  const double mid = 0.5 * (t0 + t1);
  const double jac = std::fabs(half);
  for (int i = 0; i < rule.size(); ++i) {
    const BeamSection sec = section_at(mid + half * rule.nodes[i]);
    const double w = rule.weights[i] * jac * std::fabs(sec.ds_dt);
    const double h = sec.half_thickness_m;
    const double area = 2.0 * h * b;
    const double inertia = 2.0 * h * h * h * b / 3.0;  // (2h)^3 b / 12
    const double moment = ca * (load.lever_m - sec.s_m) - sa * load.offset_m;  // per unit force
    c.bending_m_N += w * moment * moment / (el.youngs_modulus_Pa * inertia);
    c.shear_m_N += w * el.shear_factor * ca * ca / (el.shear_modulus_Pa * area);
    c.axial_m_N += w * sa * sa / (el.youngs_modulus_Pa * area);
  }
  return c;
}

/// Sainsot, Velex & Duverger 2004 (J. Mech. Des. 126:748), Table 1:
/// X* = A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F for
/// X* in {L*, M*, P*, Q*}, fitted for h_f = r_f/r_int in [1.4, 7] and
/// theta_f in [0.01, 0.12] rad.
struct FilletCoefficients {
  double L = 0, M = 0, P = 0, Q = 0;
};
FilletCoefficients sainsot_coefficients(double h_f, double theta_f_rad);

/// Sainsot et al. 2004, body (fillet-foundation) compliance [m/N]
///   1/k_f = cos^2(a_m) / (E b) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2 a_m)],
/// u_f: distance from the root circle to where the load line crosses the tooth
/// centreline [m]; S_f = 2 r_f theta_f, the root-circle arc of the tooth [m];
/// a_m: the load angle alpha1 [rad]; E: effective modulus [Pa]; b [m].
double fillet_compliance(const FilletCoefficients& c, double u_f_m, double s_f_m, double alpha_m_rad,
                         double modulus_Pa, double face_width_m);

/// Half angle theta_f [rad] subtended at the gear axis by the tooth at its
/// root circle, between the centreline and the point where the rack-generated
/// fillet (tool tip radius rho_f* m) meets the root circle:
///   theta_f = (2/z) [pi/4 + h_f* tan(a0) + rho_f* (1 - sin a0)/cos a0],
/// independent of the profile shift (the rack's tip line offset is fixed in
/// the rack frame). Used for internal teeth too (rack approximation of the
/// shaper-cut ring space).
double fillet_half_angle(const geometry::GearSpec& spec);

/// Hertzian contact compliance of a line contact of length b [m/N], Yang &
/// Lin (1987): 1/k_h = 4 (1 - nu^2) / (pi E b) for equal materials; for
/// different materials 1/k_h = (2/(pi b)) [(1-nu_1^2)/E_1 + (1-nu_2^2)/E_2],
/// which reduces to it. Independent of the position along the line of action.
double hertz_compliance(const geometry::Material& a, const geometry::Material& b, double face_width_m);

/// How one tooth is modelled.
struct ToothModelOptions {
  ElasticState elastic_state = ElasticState::PlaneStrain;
  int quadrature_points = 24;            ///< Gauss-Legendre points per beam segment
  double shear_factor = 1.2;             ///< Tian 2004
  bool include_root_segment = true;      ///< straight segment between r_f and r_b when r_f < r_b
  bool include_fillet_foundation = true; ///< Sainsot et al. 2004 body term
  /// h_f = r_f / r_int of Sainsot's fit [-]: the root radius over the radius
  /// at which the body is held (the bore of an external gear). For a ring,
  /// the equivalent body depth below the tooth root (docs/stiffness.md §1.5).
  double body_ratio = 1.0 / 0.3;
};

/// Where and how the unit force acts on the tooth for a contact at radius r.
struct ToothLoad {
  BeamLoad beam;           ///< in the beam frame (root section at s = 0)
  double pressure_angle_rad = 0;  ///< involute pressure angle at r
  double half_angle_rad = 0;      ///< half angular tooth thickness at r
  double u_f_m = 0;               ///< Sainsot's u_f
};

/// One gear's tooth, set up once (quadrature rule, fillet coefficients) and
/// evaluated at many contact radii. Not for per-time-step use: evaluation
/// costs a few hundred flops per segment and is meant for building tables.
class ToothModel {
public:
  /// Throws pw::InputError (via make_geometry) for an invalid spec, or naming
  /// `quadrature_points` / `body_ratio` / `shear_factor` when out of range.
  ToothModel(const geometry::GearSpec& spec, const ToothModelOptions& options = {});

  /// Compliance parts for a contact at radius r [m]; r must lie on the
  /// involute flank: [max(r_b, r_f), r_a] for an external tooth, [r_a, r_f] for
  /// a ring tooth (throws pw::InputError naming "contact_radius_m" otherwise).
  ToothCompliance compliance(double contact_radius_m) const;

  /// The load geometry used by compliance() (exposed for tests and docs).
  ToothLoad load_at(double contact_radius_m) const;

  const geometry::GearSpec& spec() const { return spec_; }
  const geometry::GearGeometry& geometry() const { return geo_; }
  const FilletCoefficients& fillet_coefficients() const { return fillet_; }
  double fillet_half_angle_rad() const { return theta_f_; }
  /// Centreline coordinate (distance from the axis) of the root section [m].
  double root_section_m() const { return x_root_; }

private:
  geometry::GearSpec spec_;
  geometry::GearGeometry geo_;
  ToothModelOptions opt_;
  GaussLegendreRule rule_;
  BeamElasticity el_;
  FilletCoefficients fillet_;
  double theta_f_ = 0;
  double x_root_ = 0;  ///< axis coordinate of the root section's flank points [m]
  bool internal_ = false;
  bool straight_segment_ = false;  ///< external, r_f < r_b, segment included
  double r_beam_root_ = 0;         ///< radius where the beam is clamped [m]
};

/// Convenience: ToothModel(spec, options).compliance(r).
ToothCompliance tooth_compliance(const geometry::GearSpec& spec, double contact_radius_m,
                                 const ToothModelOptions& options = {});

} // namespace pw::stiffness
