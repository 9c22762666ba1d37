// The engineering summary of one simulation (docs/cli.md, "simulate"): what a
// gear engineer reads first, as a Markdown table -- printed after `simulate`
// and written by `simulate --report FILE.md`.
#pragma once

#include "config/stage.hpp"
#include "model/result.hpp"

#include <string>

namespace pw::app {

/// sigma_Hlim = 1500 MPa: ISO 6336-5:2016 Fig. 9(a), case-hardened wrought steel,
/// material quality MQ -- the usual planetary-stage material. The default of
/// `simulate --allowable-contact-stress-pa`; a through-hardened steel is far lower
/// (ISO 6336-5 Fig. 5: 600-900 MPa), so the summary always prints which value it used.
inline constexpr double kDefaultAllowableContactStressPa = 1.5e9;

/// The summary: operating point, per mesh family the static, mean and largest
/// dynamic mesh force, the dynamic factor, the largest Hertzian contact pressure
/// (where, and against `allowable_contact_stress_Pa`), the load-sharing factor per
/// planet, the efficiency; for wear runs the largest wear depth per flank family
/// and where, the backlash growth and why the run stopped early (if it did).
/// Units: N, MPa, um, mm -- one unit per quantity, named in each header.
/// The warm-up ended in a steady state: the result's periodicity_residual is within
/// solver.periodicity_tolerance (else the recording is of a transient).
bool reached_steady_state(const model::SimulationConfig& config, const model::SimulationResult& result);

std::string engineering_summary(const model::SimulationConfig& config, const model::SimulationResult& result,
                                double allowable_contact_stress_Pa);

} // namespace pw::app
