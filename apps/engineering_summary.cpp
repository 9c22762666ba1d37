#include "engineering_summary.hpp"

#include "core/format.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace pw::app {
namespace {

double scalar_or_nan(const model::SimulationResult& r, const std::string& name) {
  const model::Scalar* s = r.find_scalar(name);
  return s ? s->value : std::numeric_limits<double>::quiet_NaN();
}

void mesh_table(std::string& o, const model::SimulationResult& r, double allowable_Pa) {
  o += "| mesh | static force [N] | mean force [N] | largest force [N] | dynamic factor K_v | "
       "largest contact pressure [MPa] | pressure / allowable | where |\n";
  o += "|---|---|---|---|---|---|---|---|\n";
  for (const char* fam : {"sun_planet", "planet_ring"}) {
    const std::string b = std::string("mesh_load/") + fam + "/";
    const double p0 = scalar_or_nan(r, b + "max_contact_pressure");
    const double pos = scalar_or_nan(r, b + "max_contact_pressure_position");
    const double planet = scalar_or_nan(r, b + "max_contact_pressure_planet");
    o += std::string("| ") + fam + " | " + fmt("%.1f", scalar_or_nan(r, b + "static_force")) + " | " +
         fmt("%.1f", scalar_or_nan(r, b + "mean_force")) + " | " + fmt("%.1f", scalar_or_nan(r, b + "max_force")) +
         " | " + fmt("%.3f", scalar_or_nan(r, b + "dynamic_factor")) + " | " + fmt("%.1f", p0 / 1e6) + " | " +
         fmt("%.3f", p0 / allowable_Pa) + " | planet " + fmt("%.0f", planet) + ", " + fmt("%+.2f", pos * 1e3) +
         " mm from the pitch point |\n";
  }
  o += "\n*where*: along the line of action, positive towards the driving gear's tip (the sun's in sun_planet, "
       "the planet's in planet_ring). Contact pressure: Hertzian peak p0 = sqrt(F' E* / (pi R)) of the most loaded "
       "tooth pair at its simulated load (not ISO 6336-2's nominal stress with its factors); allowable " +
       fmt("%.0f", allowable_Pa / 1e6) + " MPa (`--allowable-contact-stress-pa`).\n";
}

void wear_table(std::string& o, const model::WearHistory& w) {
  o += "\n## Wear after " + fmt("%.6g", w.mesh_cycles.back()) + " mesh cycles\n\n";
  o += "| flank family | largest wear depth [um] | tooth | where [mm from the pitch point, + towards the flank's tip] "
       "|\n|---|---|---|---|\n";
  for (const auto& fh : w.flanks) {
    const std::size_t per = static_cast<std::size_t>(fh.teeth) * static_cast<std::size_t>(fh.elements);
    if (per == 0 || fh.depth_m.size() < per) continue;
    const std::size_t last = fh.depth_m.size() - per;
    const auto it = std::max_element(fh.depth_m.begin() + static_cast<std::ptrdiff_t>(last), fh.depth_m.end());
    const std::size_t k = static_cast<std::size_t>(it - fh.depth_m.begin()) - last;
    const std::size_t tooth = k / static_cast<std::size_t>(fh.elements), el = k % static_cast<std::size_t>(fh.elements);
    o += "| " + fh.name + " | " + fmt("%.4g", *it * 1e6) + " | " + std::to_string(tooth) + " | " +
         fmt("%+.2f", fh.distance_from_pitch_point_m[el] * 1e3) + " |\n";
  }
  if (w.backlash_m.size() >= 4) {
    const std::size_t n = w.backlash_m.size();
    o += "\nBacklash [um]: sun_planet " + fmt("%.4g", w.backlash_m[0] * 1e6) + " -> " +
         fmt("%.4g", w.backlash_m[n - 2] * 1e6) + ", planet_ring " + fmt("%.4g", w.backlash_m[1] * 1e6) + " -> " +
         fmt("%.4g", w.backlash_m[n - 1] * 1e6) + "\n";
  }
  o += w.stop_reason.empty() ? std::string("\nThe run reached its mesh cycles.\n")
                             : "\n**Stopped early:** " + w.stop_reason + "\n";
}

} // namespace

bool reached_steady_state(const model::SimulationConfig& c, const model::SimulationResult& r) {
  return scalar_or_nan(r, "periodicity_residual") <= c.solver.periodicity_tolerance;
}

std::string engineering_summary(const model::SimulationConfig& c, const model::SimulationResult& r,
                                double allowable_Pa) {
  std::string o = "# Engineering summary\n\n";
  o += "Operating point: " + fmt("%.6g", c.operating.input_speed_rpm) + " rpm, " +
       fmt("%.6g", c.operating.input_power_W) + " W, input torque " + fmt("%.4g", scalar_or_nan(r, "input_torque")) +
       " N m, mesh frequency " + fmt("%.5g", scalar_or_nan(r, "mesh_frequency")) + " Hz, " +
       std::to_string(c.stage.planet_count) + " planets. Loads over the recorded " +
       fmt("%.0f", static_cast<double>(c.solver.record_mesh_cycles)) + " mesh periods, every time step.\n\n";
  const double residual = scalar_or_nan(r, "periodicity_residual");
  if (!reached_steady_state(c, r))
    o += "**Warning: not a steady state.** The warm-up stopped after " +
         fmt("%.0f", scalar_or_nan(r, "warmup_mesh_cycles")) + " mesh periods with a periodicity residual of " +
         fmt("%.3g", residual) + " (solver.periodicity_tolerance " + fmt("%.3g", c.solver.periodicity_tolerance) +
         "): the loads below are those of a transient. Raise solver.warmup_max_mesh_cycles, or check the operating "
         "point.\n\n";
  mesh_table(o, r, allowable_Pa);
  o += "\nLoad-sharing factor per planet (N mean F_sp,i / sum mean F_sp):";
  for (int i = 0; i < c.stage.planet_count; ++i)
    o += " " + fmt("%.4f", scalar_or_nan(r, "load_sharing_factor/" + std::to_string(i)));
  // An efficiency is a steady state's energy balance: of a transient's record (the warm-up
  // cut short, the mean speed still drifting) T_load Omega_c / P can be anything, 1.65 measured.
  const double efficiency = scalar_or_nan(r, "efficiency");
  if (reached_steady_state(c, r) && efficiency > 0 && efficiency <= 1)
    o += ". Mesh efficiency (friction losses): " + fmt("%.4f", efficiency) + ".\n";
  else
    o += ". Mesh efficiency: not given, the record is not of a steady state (T_load Omega_c / P = " +
         fmt("%.4g", efficiency) + " there).\n";
  if (!r.wear.mesh_cycles.empty()) wear_table(o, r.wear);
  return o;
}

} // namespace pw::app
