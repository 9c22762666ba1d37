// Mesh geometry along the line of action, stage assembly and mesh phasing.
// Derivations, sign conventions and sources: docs/derivation-geometry.md
// (section numbers below refer to it).
#include "geometry/mesh.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace pw::geometry {
namespace {

/// Parameter name for an error message: "stage.sun" + "teeth" -> "stage.sun.teeth".
std::string key(const std::string& label, const char* field) {
  return label.empty() ? std::string(field) : label + "." + field;
}

/// make_geometry() names the bare GearSpec field; prefix it with the label so
/// that the user sees the key he wrote.
GearGeometry labelled_geometry(const GearSpec& spec, const std::string& label) {
  try {
    return make_geometry(spec);
  } catch (const InputError& e) {
    if (label.empty()) throw;
    const std::string what = e.what();
    const std::string prefix = e.parameter() + ": ";
    const std::string bare = what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
    throw InputError(label + "." + e.parameter(), bare);
  }
}

const char* gear_word(const GearSpec& g) { return g.kind == GearKind::Internal ? "internal gear" : "gear"; }

/// Non-negative remainder of n modulo z (tooth indices are in [0, z)).
int wrap_index(long long n, int z) {
  const long long r = n % z;
  return static_cast<int>(r < 0 ? r + z : r);
}

/// x - round(x): signed distance to the nearest integer, in [-1/2, 1/2].
double off_integer(double x) { return x - std::round(x); }

/// Working pressure angle at zero backlash (§2.1). External: the tooth
/// thicknesses on the working pitch circles fill the pitch (ISO 21771);
/// internal, with gear.hpp's shift convention (x > 0 thins the ring tooth):
/// inv a' = inv a + 2 tan a (x_ring - x_pinion) / (z_ring - z_pinion).
double zero_backlash_pressure_angle(const GearSpec& a, const GearSpec& b, const std::string& label_b) {
  const double a0 = a.pressure_angle_rad;
  const bool internal = b.kind == GearKind::Internal;
  const double za = a.teeth;
  const double zb = b.teeth;
  const double inv_w = involute(a0) + 2.0 * std::tan(a0) *
                                          (internal ? (b.profile_shift - a.profile_shift) / (zb - za)
                                                    : (a.profile_shift + b.profile_shift) / (za + zb));
  // Beyond 60 deg no spur gear pair works (and inverse_involute is only
  // reliable well below 73 deg).
  require(inv_w > 0 && inv_w <= involute(kPi / 3), key(label_b, "profile_shift"),
          "the profile shifts give inv(alpha') = ", inv_w, ", outside (0, inv(60 deg)]; x_a = ", a.profile_shift,
          ", x_b = ", b.profile_shift);
  return inverse_involute(inv_w);
}

/// Roll distance of the tip point of gear g: sqrt(r_a^2 - r_b^2).
double tip_roll(const GearGeometry& g) { return g.base_radius_m * roll_angle_at(g, g.tip_radius_m); }

} // namespace

double zero_backlash_centre_distance(const GearSpec& a, const GearSpec& b) {
  const bool internal = b.kind == GearKind::Internal;
  require(!internal || b.teeth > a.teeth, "teeth", "an internal gear needs more teeth than its pinion, got ", b.teeth,
          " <= ", a.teeth);
  const double alpha_w = zero_backlash_pressure_angle(a, b, "");
  const double z_sum = internal ? b.teeth - a.teeth : a.teeth + b.teeth;
  return 0.5 * a.module_m * z_sum * std::cos(a.pressure_angle_rad) / std::cos(alpha_w);
}

namespace {
/// Roll distance [m] up to which the rack's flank end point, a distance e = (h_FfP* - x) m inside the
/// reference circle, cuts away the involute it generated (an undercut gear, rho_F < 0 in
/// form_roll_distance). In the gear's frame that point traces a trochoid: with w = -e tan(a0) - r phi
/// (its abscissa beside the pitch point while the gear turns by phi) and h = r - e, its radius is
/// hypot(w, h) and its polar angle atan2(h, w) - phi; the involute its flank generated has the polar
/// angle pi/2 - inv(alpha_rho) + inv(a0) at radius rho (cos alpha_rho = r_b / rho), the tooth's
/// material on the side of smaller angles. The involute is cut where the trochoid reaches that side;
/// the largest roll distance sqrt(rho^2 - r_b^2) of such a point is the undercut's end. Scanned over
/// the trochoid's points up to roll |rho_F| (never beyond: checked against a finer scan for
/// z = 8..17, where it ends at 0.38..0.49 |rho_F|), the last crossing refined by bisection.
double undercut_roll_distance(const GearSpec& s, const GearGeometry& g, double rho_f) {
  const double a0 = s.pressure_angle_rad, r = g.reference_radius_m, rb = g.base_radius_m;
  const double e = (s.dedendum_coef - s.root_fillet_coef * (1.0 - std::sin(a0)) - s.profile_shift) * s.module_m;
  const double h = r - e;
  if (!(h > 0) || !(h < rb)) return 0.0;  // the flank end stays outside the base circle: no cut
  // Whether the trochoid's point at roll distance `roll` (radius hypot(r_b, roll)) on the branch
  // `side` (sign of w) lies on the tooth's side of the involute.
  const auto cut = [&](double roll, double side) {
    const double rho2 = rb * rb + roll * roll;
    const double w = side * std::sqrt(rho2 - h * h);
    const double phi = (-e * std::tan(a0) - w) / r;
    const double theta_trochoid = std::atan2(h, w) - phi;
    const double theta_involute = 0.5 * kPi - involute(std::acos(rb / std::sqrt(rho2))) + involute(a0);
    return theta_trochoid < theta_involute;
  };
  // Sampled by roll distance, not by the trochoid's abscissa: near the base circle a roll distance of
  // 1e-3 m is an abscissa window of 1e-6 m, which a scan of the abscissa steps over.
  constexpr int kScan = 4000;
  const double span = -rho_f;
  double best = 0.0;
  for (double side : {-1.0, 1.0})
    for (int i = kScan; i > 0; --i) {  // from the top: the first cut sample bounds the cut's end
      const double hi = span * i / kScan, lo = span * (i - 1) / kScan;
      if (!cut(hi, side) && !cut(std::fmax(lo, 1e-9 * span), side)) continue;
      if (cut(hi, side)) {
        best = std::fmax(best, hi);
        break;
      }
      double a = lo, b = hi;  // a cuts, b does not
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (a + b);
        (cut(mid, side) ? a : b) = mid;
      }
      best = std::fmax(best, a);
      break;
    }
  return best;
}
} // namespace

double form_roll_distance(const GearSpec& s, const GearGeometry& g) {
  // The tool's straight flank ends h_FfP = (h_f* - rho_f* (1 - sin a0)) m from
  // its datum line (the tip round takes the rest of the dedendum, ISO 53). The
  // rack generates the involute only with that straight part; its end meets
  // the gear on the generating line of action, h/sin a0 from the pitch point
  // on the reference circle, which is r sin a0 from T (§2.4, ISO 21771 d_Ff).
  const double sa = std::sin(s.pressure_angle_rad);
  const double h_ff = (s.dedendum_coef - s.root_fillet_coef * (1.0 - sa)) * s.module_m;
  const double shift = s.profile_shift * s.module_m;
  if (s.kind == GearKind::External) {
    const double rho_f = g.reference_radius_m * sa - (h_ff - shift) / sa;
    // Beyond T the straight flank generates no involute; its end cuts away the involute near the
    // base circle (undercut), and the involute starts where that cut ends.
    return rho_f >= 0 ? rho_f : undercut_roll_distance(s, g, rho_f);
  }
  // Internal: the datum is moved outwards by x m (gear.hpp convention) and the
  // form point lies beyond the pitch point, away from T.
  return g.reference_radius_m * sa + (h_ff + shift) / sa;
}

MeshGeometry make_mesh(const GearSpec& a, const GearSpec& b, double centre_distance_m, const std::string& label_a,
                       const std::string& label_b) {
  require(a.kind == GearKind::External, key(label_a, "kind"),
          "the driving member of a mesh must be an external gear (sun or planet)");
  const bool internal = b.kind == GearKind::Internal;
  require(std::fabs(a.module_m - b.module_m) <= 1e-12 * a.module_m, key(label_b, "module_m"),
          "meshing gears need equal modules, got ", b.module_m, " m against ", a.module_m, " m");
  require(std::fabs(a.pressure_angle_rad - b.pressure_angle_rad) <= 1e-12, key(label_b, "pressure_angle_rad"),
          "meshing gears need equal pressure angles, got ", b.pressure_angle_rad, " rad against ",
          a.pressure_angle_rad, " rad");
  const GearGeometry ga = labelled_geometry(a, label_a);
  const GearGeometry gb = labelled_geometry(b, label_b);
  require(!internal || b.teeth > a.teeth, key(label_b, "teeth"), "an internal gear needs more teeth than its pinion (",
          a.teeth, "), got ", b.teeth);

  // Rack undercut of an external gear (z below 2 (h_FfP* - x)/sin^2 a0) is no error by itself: its
  // involute starts where the cut ends (form_roll_distance). Contact reaching into the cut is, below
  // (a mate's tips would meet a flank the rack removed).

  // Working centre distance and pressure angle (§2.1).
  const double rba = ga.base_radius_m;
  const double rbb = gb.base_radius_m;
  const double rb_sum = internal ? rbb - rba : rba + rbb;
  const double alpha0_w = zero_backlash_pressure_angle(a, b, label_b);
  const double a0_w = rb_sum / std::cos(alpha0_w);
  double aw = a0_w;
  double alpha_w = alpha0_w;
  if (centre_distance_m > 0) {
    require(std::isfinite(centre_distance_m), "centre_distance_m", "must be finite, got ", centre_distance_m);
    // Moving the centres together (external) or apart (internal) beyond the
    // zero-backlash distance makes the teeth overlap.
    if (internal) {
      require(centre_distance_m <= a0_w * (1 + 1e-9) && centre_distance_m > rb_sum, "centre_distance_m", "must lie in (",
              rb_sum, ", ", a0_w, "] m for this internal mesh (zero-backlash distance ", a0_w, " m), got ",
              centre_distance_m, " m");
    } else {
      require(centre_distance_m >= a0_w * (1 - 1e-9), "centre_distance_m", "must be >= the zero-backlash distance ",
              a0_w, " m (the teeth would overlap), got ", centre_distance_m, " m");
    }
    aw = centre_distance_m;
    alpha_w = std::acos(std::fmin(1.0, rb_sum / aw));
  }

  // Tip-to-root clearance (the tip circle of one gear must clear the root
  // circle of the other on the line of centres).
  const double clear_a = internal ? gb.tip_radius_m - aw - ga.root_radius_m : aw - gb.tip_radius_m - ga.root_radius_m;
  const double clear_b = internal ? gb.root_radius_m - aw - ga.tip_radius_m : aw - ga.tip_radius_m - gb.root_radius_m;
  require(clear_a >= -1e-12 * aw, key(label_b, "addendum_coef"), "the tip circle of the ", gear_word(b),
          " (r_a = ", gb.tip_radius_m, " m) reaches ", -clear_a, " m into the root circle of its mate (r_f = ",
          ga.root_radius_m, " m) at centre distance ", aw, " m");
  require(clear_b >= -1e-12 * aw, key(label_a, "addendum_coef"), "the tip circle (r_a = ", ga.tip_radius_m,
          " m) reaches ", -clear_b, " m into the root circle of the ", gear_word(b), " (r_f = ", gb.root_radius_m,
          " m) at centre distance ", aw, " m");

  // Path of contact on the line of action (§2.2, §2.3).
  MeshGeometry m;
  m.kind = b.kind;
  m.centre_distance_m = aw;
  m.working_pressure_angle_rad = alpha_w;
  m.base_pitch_m = ga.base_pitch_m;
  m.base_radius_a_m = rba;
  m.base_radius_b_m = rbb;
  m.tangent_distance_m = aw * std::sin(alpha_w);
  m.pitch_point_m = rba * std::tan(alpha_w);
  const double L = m.tangent_distance_m;
  const double rho_tip_b = tip_roll(gb);
  m.start_active_m = internal ? rho_tip_b - L : L - rho_tip_b;
  m.end_active_m = tip_roll(ga);

  // Involute interference: the contact must stay on the involutes, i.e.
  // between T_A and T_B (external) or beyond T_A (internal; T_B lies behind).
  require(m.start_active_m >= 0, key(label_a, "profile_shift"), "interference: the tips of the ", gear_word(b),
          " (", label_b.empty() ? "b" : label_b, ") meet this gear's flank ", -m.start_active_m,
          " m below its base circle (contact would start at xi = ", m.start_active_m,
          " m < 0 on the line of action); increase this gear's profile shift or reduce the mate's addendum");
  if (!internal) {
    require(m.end_active_m <= L, key(label_b, "profile_shift"), "interference: the tips of the driving gear (",
            label_a.empty() ? "a" : label_a, ") meet this gear's flank ", m.end_active_m - L,
            " m below its base circle (contact would end at xi = ", m.end_active_m, " m > L = ", L,
            " m); increase this gear's profile shift or reduce the mate's addendum");
  }

  // Undercut (§2.4): the path of contact must stay on the involute the rack left, above the roll
  // distance where its cut ends (form_roll_distance of an undercut gear).
  const double a_sin2 = std::sin(a.pressure_angle_rad) * std::sin(a.pressure_angle_rad);
  for (int k = 0; k < 2; ++k) {
    const GearSpec& g = k == 0 ? a : b;
    const GearGeometry& gg = k == 0 ? ga : gb;
    if (g.kind != GearKind::External) continue;
    const double h_ff = g.dedendum_coef - g.root_fillet_coef * (1.0 - std::sin(g.pressure_angle_rad));
    if (!(2.0 * (h_ff - g.profile_shift) / a_sin2 > g.teeth)) continue;  // not undercut
    const double cut_end = form_roll_distance(g, gg);
    const double lowest = k == 0 ? m.start_active_m : L - m.end_active_m;  // lowest contact, roll on g
    require(lowest >= cut_end, key(k == 0 ? label_a : label_b, "teeth"), "the generating rack undercuts this gear (z = ",
            g.teeth, ", profile_shift x = ", g.profile_shift, " below z_min = 2 (h_FfP* - x)/sin^2(alpha) = ",
            2.0 * (h_ff - g.profile_shift) / a_sin2, ", h_FfP* = h_f* - rho_f* (1 - sin alpha) = ", h_ff,
            ") and removes its involute up to roll distance ", cut_end, " m, but its mate's tips reach down to ",
            lowest, " m: use more teeth or profile_shift >= ", h_ff - 0.5 * g.teeth * a_sin2,
            " (no undercut), or a smaller addendum of the mate");
  }

  m.contact_ratio = (m.end_active_m - m.start_active_m) / m.base_pitch_m;
  require(m.contact_ratio >= 1.0, key(label_a, "addendum_coef"), "contact ratio ", m.contact_ratio,
          " < 1: the path of contact [", m.start_active_m, ", ", m.end_active_m,
          "] m is shorter than the base pitch ", m.base_pitch_m,
          " m, so the mesh loses contact between pairs; increase the addendum coefficients");

  // Fillet diagnostics (§2.4): contact beyond a form circle meets the fillet.
  const double rho_fa = form_roll_distance(a, ga);
  const double rho_fb = form_roll_distance(b, gb);
  m.form_radius_a_m = std::hypot(rba, rho_fa);
  m.form_radius_b_m = std::hypot(rbb, rho_fb);
  m.fillet_overlap_a_m = std::fmax(0.0, rho_fa - m.start_active_m);
  m.fillet_overlap_b_m =
      internal ? std::fmax(0.0, (L + m.end_active_m) - rho_fb) : std::fmax(0.0, rho_fb - (L - m.end_active_m));
  return m;
}

double contact_radius_a(const MeshGeometry& mesh, double xi_m) {
  return std::hypot(mesh.base_radius_a_m, curvature_radius_a(mesh, xi_m));
}

double contact_radius_b(const MeshGeometry& mesh, double xi_m) {
  return std::hypot(mesh.base_radius_b_m, curvature_radius_b(mesh, xi_m));
}

StageGeometry make_stage_geometry(const model::StageSpec& spec) {
  const std::string S = "stage.sun", P = "stage.planet", R = "stage.ring";
  require(spec.sun.kind == GearKind::External, S, "must be an external gear");
  require(spec.planet.kind == GearKind::External, P, "must be an external gear");
  require(spec.ring.kind == GearKind::Internal, R, "must be an internal gear");
  const int n = spec.planet_count;
  require(n >= 1, "stage.planet_count", "must be >= 1, got ", n);

  StageGeometry geo;
  geo.sun = labelled_geometry(spec.sun, S);
  geo.planet = labelled_geometry(spec.planet, P);
  geo.ring = labelled_geometry(spec.ring, R);
  // Each mesh at its own zero-backlash distance; the check below makes them
  // one carrier radius (to 1e-6, far below manufacturing tolerances).
  geo.sun_planet = make_mesh(spec.sun, spec.planet, 0.0, S, P);
  geo.planet_ring = make_mesh(spec.planet, spec.ring, 0.0, P, R);

  const int zs = spec.sun.teeth, zp = spec.planet.teeth, zr = spec.ring.teeth;
  const double a_sp = geo.sun_planet.centre_distance_m;
  const double a_pr = geo.planet_ring.centre_distance_m;
  if (std::fabs(a_sp - a_pr) > 1e-6 * a_sp) {
    const bool unshifted = spec.sun.profile_shift == 0 && spec.planet.profile_shift == 0 && spec.ring.profile_shift == 0;
    require(!unshifted, R + ".teeth", "unshifted gears need Zr = Zs + 2 Zp = ", zs + 2 * zp, ", got Zr = ", zr,
            " (sun-planet centre distance ", a_sp, " m, planet-ring ", a_pr,
            " m); change the teeth or equalise the centre distances with profile shifts");
    // The ring shift that would move the planet-ring mesh to a_sp (§2.1 inverted).
    const double a0 = spec.ring.pressure_angle_rad;
    const double c = 0.5 * spec.ring.module_m * (zr - zp) * std::cos(a0) / a_sp;
    std::string hint = "no ring profile shift can match it";
    if (c < 1) {
      const double x_r = spec.planet.profile_shift + (involute(std::acos(c)) - involute(a0)) * (zr - zp) / (2 * std::tan(a0));
      hint = detail::concat("stage.ring.profile_shift = ", x_r, " would match it");
    }
    require(false, R + ".profile_shift", "the sun-planet and planet-ring zero-backlash centre distances differ (",
            a_sp, " m vs ", a_pr, " m, relative ", std::fabs(a_sp - a_pr) / a_sp,
            " > 1e-6), so the planets cannot sit on one carrier radius; ", hint);
  }
  geo.carrier_radius_m = a_sp;

  // Planet angles and the assembly condition (§4.1).
  const int z_sum = zs + zr;
  const bool equal = spec.planet_angles_rad.empty();
  const std::string angle_key = equal ? "stage.planet_count" : "stage.planet_angles_rad";
  if (equal) {
    require(z_sum % n == 0, "stage.planet_count", "equally spaced planets need (Zs + Zr)/N to be an integer, got (", zs,
            " + ", zr, ")/", n, " = ", static_cast<double>(z_sum) / n, "; use N dividing ", z_sum,
            " or unequal stage.planet_angles_rad");
    for (int i = 0; i < n; ++i) geo.planet_angles_rad.push_back(2 * kPi * i / n);
  } else {
    const auto& psi = spec.planet_angles_rad;
    require(psi.size() == static_cast<std::size_t>(n), "stage.planet_angles_rad", "must list one angle per planet (",
            n, "), got ", psi.size());
    require(std::fabs(psi[0]) <= 1e-12, "stage.planet_angles_rad", "angles are measured from planet 0, so psi_0 must be 0, got ",
            psi[0]);
    for (int i = 1; i < n; ++i) {
      require(std::isfinite(psi[i]) && psi[i] > psi[i - 1] && psi[i] < 2 * kPi, "stage.planet_angles_rad",
              "must increase within [0, 2 pi), got psi_", i, " = ", psi[i], " after ", psi[i - 1]);
    }
    for (int i = 0; i < n; ++i) {
      const double q = psi[i] * z_sum / (2 * kPi);
      require(std::fabs(off_integer(q)) <= 1e-6, "stage.planet_angles_rad", "planet ", i, " at psi = ", psi[i],
              " rad cannot mesh with sun and ring at once: psi (Zs + Zr)/(2 pi) = ", q,
              " must be an integer; the nearest assemblable angle is ", 2 * kPi * std::round(q) / z_sum, " rad");
    }
    geo.planet_angles_rad = psi;
  }

  // Neighbouring planets' tip circles must not touch.
  const double ra = geo.planet.tip_radius_m;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double dpsi = geo.planet_angles_rad[j] - geo.planet_angles_rad[i];
      const double gap = 2 * a_sp * std::fabs(std::sin(0.5 * dpsi));
      if (gap > 2 * ra) continue;
      const int n_max = static_cast<int>(std::ceil(kPi / std::asin(std::fmin(1.0, ra / a_sp)))) - 1;
      require(false, angle_key, "planets ", i, " and ", j, " collide: their centres are ", gap,
              " m apart but their tip circles need more than 2 r_a = ", 2 * ra, " m (carrier radius ", a_sp,
              " m); at most ", n_max, " equally spaced planets fit");
    }
  }
  return geo;
}

namespace {

/// Per-stage constants of the flank construction (§3, §4).
struct Flanks {
  double zs, zp, zr;
  double beta_s, beta_p, beta_r;  // half base tooth angles (gear.hpp)
  double rbs, rbp, rbr;
  const MeshGeometry* sp;
  const MeshGeometry* pr;
};

Flanks flanks_of(const model::StageSpec& spec, const StageGeometry& geo) {
  return {static_cast<double>(spec.sun.teeth),
          static_cast<double>(spec.planet.teeth),
          static_cast<double>(spec.ring.teeth),
          geo.sun.half_base_tooth_angle_rad,
          geo.planet.half_base_tooth_angle_rad,
          geo.ring.half_base_tooth_angle_rad,
          geo.sun.base_radius_m,
          geo.planet.base_radius_m,
          geo.ring.base_radius_m,
          &geo.sun_planet,
          &geo.planet_ring};
}

/// Pair 0 of one mesh: its roll coordinate, the unwrapped tooth index on the
/// body whose flank fixed it, and the centreline angle of the mate's tooth.
struct Pair0 {
  double xi0;
  long long tooth;
  double mate_centre_rad;
};

/// Sun-planet mesh of the planet at carrier angle psi, sun tooth 0 at sun0
/// (§3.2). The sun's drive flank is the counter-clockwise side of a tooth: its
/// involute starts on the base circle at centre + beta_s and unwinds
/// clockwise, so its contact point lies r_bs (origin - T_A) from T_A along the
/// LOA, T_A at psi - alpha'. Tooth k (centre sun0 - 2 pi k/Zs) gives
/// xi = X - k p_b. The planet flank it touches is also a counter-clockwise
/// side, origin at T_B + (L - xi)/r_bp with T_B at psi + pi - alpha'.
Pair0 sun_planet_pair0(const Flanks& f, double sun0, double psi) {
  const MeshGeometry& m = *f.sp;
  const double aw = m.working_pressure_angle_rad;
  const double pb = m.base_pitch_m;
  const double X = f.rbs * (sun0 + f.beta_s - (psi - aw));
  const double k0 = std::floor((X - m.start_active_m) / pb);
  const double xi0 = X - k0 * pb;
  const double origin_p = psi + kPi - aw + (m.tangent_distance_m - xi0) / f.rbp;
  return {xi0, static_cast<long long>(k0), origin_p - f.beta_p};
}

/// Planet-ring mesh of the planet at carrier angle psi with planet tooth 0 at
/// planet0 (§3.3). The planet drives with the clockwise side of its teeth: the
/// involute starts at centre - beta_p and unwinds counter-clockwise, so the
/// contact lies r_bp (T_A - origin) from T_A, T_A at psi + alpha' (about the
/// planet centre). Tooth j (centre planet0 + 2 pi j/Zp) gives xi = Y - j p_b.
/// The ring flank it touches is the counter-clockwise side of a ring tooth,
/// origin T_B - (L + xi)/r_br with T_B at psi + alpha' (about the ring axis).
Pair0 planet_ring_pair0(const Flanks& f, double planet0, double psi) {
  const MeshGeometry& m = *f.pr;
  const double aw = m.working_pressure_angle_rad;
  const double pb = m.base_pitch_m;
  const double Y = f.rbp * (psi + aw - (planet0 - f.beta_p));
  const double j0 = std::floor((Y - m.start_active_m) / pb);
  const double xi0 = Y - j0 * pb;
  const double origin_r = psi + aw - (m.tangent_distance_m + xi0) / f.rbr;
  return {xi0, static_cast<long long>(j0), origin_r - f.beta_r};
}

/// Angle in [-pi, pi].
double wrap_angle(double a) { return std::remainder(a, 2 * kPi); }

/// Tooth 0 of a body whose tooth with centre `centre` is some tooth k: the
/// tooth nearest to `nominal` (pitch 2 pi / z, numbered counter-clockwise).
double tooth0_near(double centre, double nominal, double z) {
  const double pitch = 2 * kPi / z;
  return wrap_angle(nominal + off_integer((centre - nominal) / pitch) * pitch);
}

} // namespace

AssemblyLayout assembly_layout(const model::StageSpec& spec, const StageGeometry& geo) {
  const Flanks f = flanks_of(spec, geo);
  AssemblyLayout lay;
  lay.sun_tooth0_rad = 0.0;
  // Each planet turned until its flank touches the sun's drive flank (zero
  // backlash fixes the rest); tooth 0 nearest to where planet 0's would be.
  for (const double psi : geo.planet_angles_rad) {
    const Pair0 p = sun_planet_pair0(f, lay.sun_tooth0_rad, psi);
    lay.planet_tooth0_rad.push_back(tooth0_near(p.mate_centre_rad, psi + kPi - kPi / f.zp, f.zp));
  }
  // The ring turned until it meshes with planet 0.
  const Pair0 p = planet_ring_pair0(f, lay.planet_tooth0_rad.front(), geo.planet_angles_rad.front());
  const double nominal = spec.planet.teeth % 2 == 0 ? 0.0 : -kPi / f.zr;
  lay.ring_tooth0_rad = tooth0_near(p.mate_centre_rad, nominal, f.zr);
  return lay;
}

std::vector<PlanetPhases> mesh_phases(const model::StageSpec& spec, const StageGeometry& geo) {
  const Flanks f = flanks_of(spec, geo);
  const AssemblyLayout lay = assembly_layout(spec, geo);
  std::vector<PlanetPhases> out;
  out.reserve(geo.planet_angles_rad.size());
  for (std::size_t i = 0; i < geo.planet_angles_rad.size(); ++i) {
    const double psi = geo.planet_angles_rad[i];
    PlanetPhases ph;

    const Pair0 sp = sun_planet_pair0(f, lay.sun_tooth0_rad, psi);
    ph.sun_planet.xi0_m = sp.xi0;
    ph.sun_planet.tooth_a0 = wrap_index(sp.tooth, spec.sun.teeth);
    // The planet was turned to touch this very flank, so the index is exact.
    const double j = (sp.mate_centre_rad - lay.planet_tooth0_rad[i]) * f.zp / (2 * kPi);
    ph.sun_planet.tooth_b0 = wrap_index(std::llround(j), spec.planet.teeth);

    const Pair0 pr = planet_ring_pair0(f, lay.planet_tooth0_rad[i], psi);
    ph.planet_ring.xi0_m = pr.xi0;
    ph.planet_ring.tooth_a0 = wrap_index(pr.tooth, spec.planet.teeth);
    // A ring tooth must sit exactly where this planet's flank needs it; that
    // is the assembly condition psi (Zs + Zr)/2 pi integer, seen from the ring.
    const double q = (pr.mate_centre_rad - lay.ring_tooth0_rad) * f.zr / (2 * kPi);
    require(std::fabs(off_integer(q)) <= 1e-6, "stage.planet_angles_rad", "planet ", i, " at psi = ", psi,
            " rad meshes with the sun but misses the ring teeth by ", off_integer(q),
            " ring pitches; psi (Zs + Zr)/(2 pi) must be an integer");
    ph.planet_ring.tooth_b0 = wrap_index(std::llround(q), spec.ring.teeth);
    out.push_back(ph);
  }
  return out;
}

int pairs_in_contact(const MeshGeometry& mesh, const MeshPhase& phase, int teeth_a, int teeth_b, double s_m,
                     std::vector<ContactPair>& out, double margin_m) {
  out.clear();
  const double pb = mesh.base_pitch_m;
  const double u = phase.xi0_m + s_m;  // xi_n = u - n p_b
  const double n_first = std::ceil((u - mesh.end_active_m - margin_m) / pb);
  const double n_last = std::floor((u - mesh.start_active_m + margin_m) / pb);
  if (!(n_first <= n_last)) return 0;
  // Tooth indices of the first pair by one modulo each; the next pairs' follow by
  // counting (this runs at every time step of every mesh).
  const long long k0 = static_cast<long long>(n_first);
  int ta = wrap_index(phase.tooth_a0 + k0, teeth_a), tb = wrap_index(phase.tooth_b0 + k0, teeth_b);
  for (double n = n_first; n <= n_last; n += 1.0) {
    out.push_back({u - n * pb, ta, tb});
    if (++ta == teeth_a) ta = 0;
    if (++tb == teeth_b) tb = 0;
  }
  return static_cast<int>(out.size());
}

double engagement_weight(const MeshGeometry& mesh, double xi_m, double half_width_m) {
  if (!(half_width_m > 0)) return (xi_m >= mesh.start_active_m && xi_m <= mesh.end_active_m) ? 1.0 : 0.0;
  const double w2 = 2 * half_width_m;
  const double in = std::clamp((xi_m - (mesh.start_active_m - half_width_m)) / w2, 0.0, 1.0);
  const double out = std::clamp(((mesh.end_active_m + half_width_m) - xi_m) / w2, 0.0, 1.0);
  return std::min(in, out);
}

} // namespace pw::geometry
