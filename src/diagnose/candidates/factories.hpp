// One factory per candidate file (registry.cpp lists them in its table).
#pragma once

#include "diagnose/candidates/candidate.hpp"

#include <memory>

namespace pw::diagnose::candidates {

std::unique_ptr<Candidate> stiffness_level();       // stiffness_level.cpp
std::unique_ptr<Candidate> damping_level();         // damping_level.cpp
std::unique_ptr<Candidate> sun_tooth_damage();      // tooth_damage.cpp
std::unique_ptr<Candidate> planet_tooth_damage();   // tooth_damage.cpp
std::unique_ptr<Candidate> ring_tooth_damage();     // tooth_damage.cpp
std::unique_ptr<Candidate> pin_error();             // pin_error.cpp
std::unique_ptr<Candidate> sun_runout();            // runout.cpp
std::unique_ptr<Candidate> carrier_runout();        // runout.cpp
std::unique_ptr<Candidate> torque_ripple();         // torque_ripple.cpp
std::unique_ptr<Candidate> worn_profile();          // worn_profile.cpp
std::unique_ptr<Candidate> friction();              // friction.cpp
std::unique_ptr<Candidate> backlash();              // backlash.cpp
std::unique_ptr<Candidate> sensor_transfer_path();  // sensor_transfer_path.cpp
std::unique_ptr<Candidate> encoder_bandwidth();     // encoder_bandwidth.cpp
std::unique_ptr<Candidate> bearing_damping();       // bearing_damping.cpp
std::unique_ptr<Candidate> tip_relief();            // tip_relief.cpp
std::unique_ptr<Candidate> engagement_ramp();       // engagement_ramp.cpp
std::unique_ptr<Candidate> housing_mount();         // housing_mount.cpp
std::unique_ptr<Candidate> motor_inertia();         // rig_inertia.cpp
std::unique_ptr<Candidate> load_inertia();          // rig_inertia.cpp
std::unique_ptr<Candidate> input_shaft();           // rig_shaft.cpp
std::unique_ptr<Candidate> output_shaft();          // rig_shaft.cpp
std::unique_ptr<Candidate> mesh_stiffness_harmonics();  // mesh_stiffness_harmonics.cpp

} // namespace pw::diagnose::candidates
