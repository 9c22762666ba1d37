// Involute spur gear: the derived circle radii and tooth-thickness function of
// a specification (GearSpec, config/gear_spec.hpp: what a designer writes down).
//
// Conventions (docs/derivation.md §1):
//  * SI units throughout: lengths [m], angles [rad].
//  * External gear: teeth point away from the axis. Internal (ring) gear: teeth
//    point towards the axis; its tip circle is *inside* its reference circle.
//  * Profile shift x [-]: for an external gear x > 0 moves the basic rack away
//    from the axis (thicker tooth at the reference circle, ISO 21771); for an
//    internal gear x > 0 also moves the profile away from the axis, which makes
//    the ring tooth *thinner* at the reference circle (the convention of KHK's
//    internal-gear tables; ISO 21771 signs internal shifts the other way).
//  * Tooth proportions from the ISO 53 basic rack: addendum h_a* m, dedendum
//    h_f* m, root fillet radius rho_f* m (defaults 1, 1.25, 0.38).
#pragma once

#include "config/gear_spec.hpp"

namespace pw::geometry {

/// Circles of an involute gear, derived from a GearSpec.
struct GearGeometry {
  double reference_radius_m = 0; ///< r = m z / 2
  double base_radius_m = 0;      ///< r_b = r cos(alpha0)
  double tip_radius_m = 0;       ///< r_a (internal: the smallest radius of a tooth)
  double root_radius_m = 0;      ///< r_f (internal: the largest radius of a tooth space)
  double base_pitch_m = 0;       ///< p_b = pi m cos(alpha0)
  /// Half the angular tooth thickness on the base circle [rad]; the tooth
  /// flank's involute starts (for an external gear) this angle either side of
  /// the tooth centreline.
  double half_base_tooth_angle_rad = 0;
};

/// inv(alpha) = tan(alpha) - alpha.
double involute(double alpha_rad);
/// Inverse of involute() on [0, pi/2): safeguarded Newton, |error| < 1e-14 rad.
double inverse_involute(double inv_alpha);

/// Derives the circles; throws pw::InputError naming the offending GearSpec
/// field for non-positive teeth/module/face width, pressure angle outside
/// (0, pi/4], negative coefficients, or a tooth that comes to a point.
GearGeometry make_geometry(const GearSpec& spec);

/// Pressure angle of the involute at radius r (r >= r_b) [rad]: acos(r_b / r).
double pressure_angle_at(const GearGeometry& g, double radius_m);

/// Half angular tooth thickness at radius r on the involute part of the flank
/// (r_b <= r) [rad]. External: pi/(2z) + 2x tan(a0)/z + inv(a0) - inv(a_r).
/// Internal (ring tooth, thickening outwards): pi/(2z) - 2x tan(a0)/z
/// - inv(a0) + inv(a_r).
double half_tooth_angle_at(const GearSpec& spec, const GearGeometry& g, double radius_m);

/// Roll angle of the involute at radius r: sqrt((r/r_b)^2 - 1) [rad]; the
/// radius of curvature of the flank there is r_b * roll angle.
double roll_angle_at(const GearGeometry& g, double radius_m);

} // namespace pw::geometry
