// What a gear designer specifies for one involute spur gear: a plain value
// type of the configuration (config/stage.hpp holds the whole stage). The
// conventions (profile shift sign, ISO 53 basic rack) are those of
// geometry/gear.hpp, which derives the circles from it; the namespace stays
// pw::geometry.
#pragma once

namespace pw::geometry {

enum class GearKind { External, Internal };

/// Linear-elastic isotropic material of a gear body.
struct Material {
  double youngs_modulus_Pa = 206e9;  ///< E [Pa] (seed Table 1)
  double shear_modulus_Pa = 79.4e9;  ///< G [Pa] (seed Table 1)
  double poisson_ratio = 0.3;        ///< nu [-] (seed Table 1)
  double density_kg_m3 = 7850.0;     ///< rho [kg/m^3], steel; seed leaves unstated
};

/// What a gear designer specifies for one spur gear.
struct GearSpec {
  int teeth = 21;                       ///< z [-], > 0 (internal: number of ring teeth)
  double module_m = 3e-3;               ///< normal module m [m]
  double pressure_angle_rad = 0.349066; ///< reference pressure angle alpha0 [rad] (seed: 20 deg)
  double profile_shift = 0.0;           ///< x [-], ISO 21771 sign convention (geometry/gear.hpp)
  double addendum_coef = 1.0;           ///< h_a* [-]
  double dedendum_coef = 1.25;          ///< h_f* [-]
  double root_fillet_coef = 0.38;       ///< rho_f* [-], tool tip radius / m
  double face_width_m = 0.05;           ///< b [m] (seed: 50 mm)
  GearKind kind = GearKind::External;
  Material material{};
};

} // namespace pw::geometry
