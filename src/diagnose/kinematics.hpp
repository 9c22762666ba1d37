// Kinematics of a planetary stage with a fixed ring, as the diagnosis needs
// it: the characteristic frequencies, the families of spectral lines each
// rotating component produces, and where each tooth meets each mesh.
//
// With n_s the sun speed [rev/s] and Zs, Zp, Zr the teeth (docs/derivation.md
// §1, §3.1):
//   f_s  = n_s                             input (sun) shaft, absolute
//   f_c  = f_s Zs / (Zs + Zr)              carrier
//   f_sr = f_s - f_c                       sun relative to the carrier
//   f_m  = Zs f_sr = Zr f_c                mesh frequency
//   f_pr = f_m / Zp                        planet spin relative to the carrier
// Mesh-cycle coordinate u = f_m t (absolute time, nominal speed): the roll
// distance of every mesh in base pitches. A tooth of the sun returns to the
// same planet every Zs mesh cycles, a planet tooth every Zp, a ring tooth
// every Zr (one carrier revolution).
//
// Line families (McFadden & Smith 1985; Inalpolat & Kahraman 2009):
//   Mesh:       a f_m                      (a = 1, 2, ...)
//   Sun:        a f_m + b f_sr             local sun damage, sun runout
//   Planet:     a f_m + b f_pr             local planet damage
//   Carrier:    a f_m + b f_c              ring damage, pin/carrier errors,
//                                          planet-pass modulation at a housing sensor
//   InputShaft: a f_m + b f_s              input torque ripple, input shaft
// (b != 0; a = 0 gives the low-frequency lines b f_X, b > 0).
#pragma once

#include "config/stage.hpp"

#include <string>
#include <vector>

namespace pw::diagnose {

/// A rotating component whose period organises a family of lines.
enum class Component { Mesh, Sun, Planet, Carrier, InputShaft };

inline constexpr Component kAllComponents[] = {Component::Mesh, Component::Sun, Component::Planet,
                                               Component::Carrier, Component::InputShaft};

/// "mesh", "sun", "planet", "carrier", "input_shaft".
const char* to_string(Component c);
/// Symbol of the component's frequency: "f_m", "f_sr", "f_pr", "f_c", "f_s".
const char* frequency_symbol(Component c);
/// One sentence: which lines, what rotates, which faults make them.
std::string family_meaning(Component c);

struct Kinematics {
  int sun_teeth = 0, planet_teeth = 0, ring_teeth = 0, planets = 0;
  double sun_Hz = 0;               ///< f_s, absolute input speed [Hz]
  double carrier_Hz = 0;           ///< f_c [Hz]
  double sun_relative_Hz = 0;      ///< f_sr = f_s - f_c [Hz]
  double planet_relative_Hz = 0;   ///< f_pr = f_m / Zp [Hz]
  double mesh_Hz = 0;              ///< f_m [Hz]

  /// Fundamental frequency of a component's family [Hz] (Mesh: f_m).
  double frequency_Hz(Component c) const;
  /// Its period in mesh cycles: Sun Zs, Planet Zp, Carrier Zr, Mesh 1,
  /// InputShaft f_m / f_s.
  double period_mesh_cycles(Component c) const;
  /// True if `mesh_cycles` whole mesh cycles hold a whole number of the
  /// family's periods (exact integer arithmetic): Mesh always, Sun if Zs
  /// divides it, Planet if Zp does, Carrier if Zr does, InputShaft if
  /// Zs Zr / (Zs + Zr) does (mesh_cycles (Zs + Zr) a multiple of Zs Zr).
  /// Over such a window every line of the family falls on a DFT bin.
  bool completes_periods(Component c, long mesh_cycles) const;
};

/// Nominal kinematics of `stage` at `input_speed_rpm`. Throws pw::InputError
/// for a non-positive speed.
Kinematics kinematics(const model::StageSpec& stage, double input_speed_rpm);

/// One spectral line: a f_m + b f_X of family X.
struct KinematicLine {
  double frequency_Hz = 0;
  Component family = Component::Mesh;
  int mesh_harmonic = 0;  ///< a
  int sideband = 0;       ///< b (0 for the mesh harmonics themselves)
  std::string label;      ///< e.g. "2 f_m - 3 f_sr"
};

/// The lines of family `family` with 0 <= a <= max_mesh_harmonic,
/// 1 <= |b| <= max_sideband (for Mesh: a f_m, a >= 1), 0 < f <= max_Hz,
/// sorted by frequency.
std::vector<KinematicLine> family_lines(const Kinematics& k, Component family, int max_mesh_harmonic,
                                        int max_sideband, double max_Hz);

/// Frequency of a component's family in carrier orders (multiples of the
/// carrier's rotation f_c): Mesh Zr, Sun Zr/Zs, Planet Zr/Zp, Carrier 1,
/// InputShaft (Zs+Zr)/Zs. The order domain is what the diagnosis compares:
/// resampled to the carrier angle, a line's order does not depend on the
/// speed, the time step or the time origin.
double carrier_orders(const Kinematics& k, Component c);

/// One spectral line in carrier orders: a Zr + b o_X of family X.
struct OrderLine {
  double order = 0;       ///< carrier orders
  Component family = Component::Mesh;
  int mesh_harmonic = 0;  ///< a
  int sideband = 0;       ///< b (0 for the mesh harmonics themselves)
  std::string label;      ///< e.g. "2 f_m - 3 f_sr"
};

/// The lines of `family` with 0 <= a <= max_mesh_harmonic, 1 <= |b| <=
/// max_sideband (Mesh: a Zr, a >= 1), 0 < order <= max_order, sorted by order.
std::vector<OrderLine> order_lines(const Kinematics& k, Component family, int max_mesh_harmonic, int max_sideband,
                                   double max_order);

/// Where each tooth meets each mesh, from the assembly phases
/// (geometry::mesh_phases; docs/derivation-geometry.md §4): tooth j of body B
/// passes the pitch point of a mesh at mesh cycles u = u_j + k P, P the body's
/// period (Zs, Zp, Zr) in mesh cycles.
class ToothMap {
public:
  explicit ToothMap(const model::SimulationConfig& config);

  enum class Mesh { SunPlanet, PlanetRing };
  /// u_j in [0, P) for tooth `tooth` of `body` (planet index `planet` for the
  /// planet's teeth, and whose mesh for the sun and ring) in `mesh` of planet
  /// `planet`. The sun meets only SunPlanet meshes, the ring only PlanetRing.
  double passage_mesh_cycle(model::Body body, int planet, int tooth, Mesh mesh) const;
  /// The tooth of `body` whose passage through `mesh` of planet `planet` is
  /// nearest to mesh cycle u (taken modulo the body's period).
  int nearest_tooth(model::Body body, int planet, Mesh mesh, double u) const;
  int teeth(model::Body body) const;

private:
  struct Phase {
    double u0 = 0;  ///< mesh cycle at which pair 0 passes the pitch point
    int a0 = 0, b0 = 0;
  };
  int zs_ = 0, zp_ = 0, zr_ = 0;
  std::vector<Phase> sun_planet_, planet_ring_;
};

} // namespace pw::diagnose
