#include "diagnose/kinematics.hpp"

#include "core/error.hpp"
#include "geometry/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pw::diagnose {

const char* to_string(Component c) {
  switch (c) {
  case Component::Mesh: return "mesh";
  case Component::Sun: return "sun";
  case Component::Planet: return "planet";
  case Component::Carrier: return "carrier";
  case Component::InputShaft: return "input_shaft";
  }
  return "unknown";
}

const char* frequency_symbol(Component c) {
  switch (c) {
  case Component::Mesh: return "f_m";
  case Component::Sun: return "f_sr";
  case Component::Planet: return "f_pr";
  case Component::Carrier: return "f_c";
  case Component::InputShaft: return "f_s";
  }
  return "?";
}

std::string family_meaning(Component c) {
  switch (c) {
  case Component::Mesh:
    return "mesh harmonics k f_m: the mean mesh excitation (stiffness and damping level, friction, tooth "
           "profile shape, backlash)";
  case Component::Sun:
    return "sidebands at k f_m +- j (f_s - f_c) and lines j (f_s - f_c): the sun's rotation relative to the "
           "carrier, the sun-fault family (local sun tooth damage, sun runout)";
  case Component::Planet:
    return "sidebands at k f_m +- j f_m/Zp and lines j f_m/Zp: a planet's spin relative to the carrier, the "
           "planet-fault family (local planet tooth damage)";
  case Component::Carrier:
    return "sidebands at k f_m +- j f_c and lines j f_c: the carrier's rotation, i.e. planets passing a ring "
           "tooth or a housing sensor (ring tooth damage, pin position errors, carrier runout, transfer path)";
  case Component::InputShaft:
    return "lines j f_s and sidebands k f_m +- j f_s: the input shaft's absolute rotation (input torque "
           "ripple)";
  }
  return "";
}

double Kinematics::frequency_Hz(Component c) const {
  switch (c) {
  case Component::Mesh: return mesh_Hz;
  case Component::Sun: return sun_relative_Hz;
  case Component::Planet: return planet_relative_Hz;
  case Component::Carrier: return carrier_Hz;
  case Component::InputShaft: return sun_Hz;
  }
  return 0;
}

double Kinematics::period_mesh_cycles(Component c) const { return mesh_Hz / frequency_Hz(c); }

bool Kinematics::completes_periods(Component c, long q) const {
  const long zs = sun_teeth, zp = planet_teeth, zr = ring_teeth;
  switch (c) {
  case Component::Mesh: return true;
  case Component::Sun: return q % zs == 0;
  case Component::Planet: return q % zp == 0;
  case Component::Carrier: return q % zr == 0;
  case Component::InputShaft: return (q * (zs + zr)) % (zs * zr) == 0;  // f_s / f_m = (Zs + Zr) / (Zs Zr)
  }
  return false;
}

Kinematics kinematics(const model::StageSpec& stage, double rpm) {
  require(std::isfinite(rpm) && rpm > 0, "operating.input_speed_rpm", "must be > 0, got ", rpm);
  Kinematics k;
  k.sun_teeth = stage.sun.teeth;
  k.planet_teeth = stage.planet.teeth;
  k.ring_teeth = stage.ring.teeth;
  k.planets = stage.planet_count;
  k.sun_Hz = rpm / 60.0;
  k.carrier_Hz = model::carrier_speed(stage, k.sun_Hz);
  k.sun_relative_Hz = k.sun_Hz - k.carrier_Hz;
  k.mesh_Hz = k.ring_teeth * k.carrier_Hz;
  k.planet_relative_Hz = k.mesh_Hz / k.planet_teeth;
  return k;
}

std::vector<KinematicLine> family_lines(const Kinematics& k, Component family, int max_a, int max_b,
                                        double max_Hz) {
  std::vector<KinematicLine> out;
  char buf[96];
  const double fx = k.frequency_Hz(family);
  for (int a = 0; a <= max_a; ++a) {
    if (family == Component::Mesh) {
      if (a == 0) continue;
      const double f = a * k.mesh_Hz;
      if (f > max_Hz) continue;
      std::snprintf(buf, sizeof buf, "%d f_m", a);
      out.push_back({f, family, a, 0, buf});
      continue;
    }
    for (int b = -max_b; b <= max_b; ++b) {
      if (b == 0 || (a == 0 && b < 0)) continue;
      const double f = a * k.mesh_Hz + b * fx;
      if (f <= 0 || f > max_Hz) continue;
      if (a == 0)
        std::snprintf(buf, sizeof buf, "%d %s", b, frequency_symbol(family));
      else
        std::snprintf(buf, sizeof buf, "%d f_m %c %d %s", a, b < 0 ? '-' : '+', std::abs(b), frequency_symbol(family));
      out.push_back({f, family, a, b, buf});
    }
  }
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.frequency_Hz < y.frequency_Hz; });
  return out;
}

double carrier_orders(const Kinematics& k, Component c) { return k.frequency_Hz(c) / k.carrier_Hz; }

std::vector<OrderLine> order_lines(const Kinematics& k, Component family, int max_a, int max_b, double max_order) {
  std::vector<OrderLine> out;
  for (const auto& l : family_lines(k, family, max_a, max_b, max_order * k.carrier_Hz * (1 + 1e-12)))
    out.push_back({l.frequency_Hz / k.carrier_Hz, l.family, l.mesh_harmonic, l.sideband, l.label});
  return out;
}

ToothMap::ToothMap(const model::SimulationConfig& config) {
  const auto geo = geometry::make_stage_geometry(config.stage);
  const auto phases = geometry::mesh_phases(config.stage, geo);
  zs_ = config.stage.sun.teeth;
  zp_ = config.stage.planet.teeth;
  zr_ = config.stage.ring.teeth;
  for (const auto& p : phases) {
    sun_planet_.push_back({(geo.sun_planet.pitch_point_m - p.sun_planet.xi0_m) / geo.sun_planet.base_pitch_m,
                           p.sun_planet.tooth_a0, p.sun_planet.tooth_b0});
    planet_ring_.push_back({(geo.planet_ring.pitch_point_m - p.planet_ring.xi0_m) / geo.planet_ring.base_pitch_m,
                            p.planet_ring.tooth_a0, p.planet_ring.tooth_b0});
  }
}

int ToothMap::teeth(model::Body body) const {
  switch (body) {
  case model::Body::Sun: return zs_;
  case model::Body::Planet: return zp_;
  case model::Body::Ring: return zr_;
  }
  return 0;
}

namespace {
int pos_mod(int a, int m) { return ((a % m) + m) % m; }
double pos_fmod(double a, double m) {
  const double r = std::fmod(a, m);
  return r < 0 ? r + m : r;
}
} // namespace

double ToothMap::passage_mesh_cycle(model::Body body, int planet, int tooth, Mesh mesh) const {
  require(planet >= 0 && planet < static_cast<int>(sun_planet_.size()), "planet", "no planet ", planet);
  const int z = teeth(body);
  require(tooth >= 0 && tooth < z, "tooth", "tooth ", tooth, " outside [0, ", z - 1, "]");
  const Phase& ph = mesh == Mesh::SunPlanet ? sun_planet_[planet] : planet_ring_[planet];
  // The body is A (sun in the sun mesh, planet in the ring mesh) or B.
  const bool is_a = (mesh == Mesh::SunPlanet && body == model::Body::Sun) ||
                    (mesh == Mesh::PlanetRing && body == model::Body::Planet);
  const int n = pos_mod(tooth - (is_a ? ph.a0 : ph.b0), z);  // pair that engages this tooth
  return pos_fmod(ph.u0 + n, z);
}

int ToothMap::nearest_tooth(model::Body body, int planet, Mesh mesh, double u) const {
  const int z = teeth(body);
  int best = 0;
  double best_d = 1e300;
  for (int j = 0; j < z; ++j) {
    const double d = pos_fmod(u - passage_mesh_cycle(body, planet, j, mesh) + 0.5 * z, z) - 0.5 * z;
    if (std::fabs(d) < best_d) {
      best_d = std::fabs(d);
      best = j;
    }
  }
  return best;
}

} // namespace pw::diagnose
