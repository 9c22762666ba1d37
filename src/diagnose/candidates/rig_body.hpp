// The two ends of the stage where a test rig attaches its machines (rig elements
// rig_inertia.cpp, rig_shaft.cpp): the input shaft turns with the sun, the output shaft with
// the carrier.
#pragma once

#include "model/simulation.hpp"

namespace pw::diagnose::candidates {

enum class RigEnd { Input, Output };

/// A machine this many times the body's own inertia is a speed source at every analysed
/// frequency: its speed does not follow the mesh forces (the largest rig inertia fitted).
constexpr double kSpeedSourceOfOwnInertia = 1e4;

/// A machine's inertia of this many times the body's own changes every line by about as much:
/// below the noise of any recording the reader accepts ('absent', the bottom of a machine
/// inertia's box).
constexpr double kAbsentOfOwnInertia = 1e-4;
/// A machine as heavy as the body doubles its inertia (a machine inertia's screening value).
constexpr double kScreenOfOwnInertia = 1.0;

/// Whether the machine's inertia at `end` is in the model: not behind a flexible shaft whose far
/// end an ideal speed control holds at the set speed (whatever its inertia).
bool machine_inertia_acts(const model::SimulationConfig& b, RigEnd end);

/// Whether the machine's inertia at `end` is the speed-source stand-in a shaft element writes when
/// the configuration states none (kSpeedSourceOfOwnInertia times the body's own, rig_shaft.cpp), or
/// heavier: a value that says "heavy enough not to follow the mesh forces", not a measured machine.
/// At the low orders of a torque ripple (k f_s) such a machine takes almost all of the ripple
/// torque, so what reaches the gears depends on an inertia nobody measured.
bool machine_is_speed_source_stand_in(const model::SimulationConfig& b, RigEnd end);

/// The body's own torsional inertia [kg m^2] as the model derives it, without any machine:
/// the sun's disc (input), or the carrier with its planets' masses at the carrier radius (output).
double own_inertia_kgm2(const model::SimulationConfig& b, RigEnd end);

} // namespace pw::diagnose::candidates
