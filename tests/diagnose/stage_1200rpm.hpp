// The operating point of the diagnose unit tests that build their recordings by
// hand (test_compare, test_locate): the seed stage (Zs 21, Zp 30, Zr 81) at
// 1200 rpm, mesh frequency 333.5 Hz, carrier revolution 0.243 s, 20 kW.
#pragma once

#include "config/stage.hpp"

namespace pw::diagnose::test {

inline model::SimulationConfig stage_1200rpm() {
  model::SimulationConfig c;
  c.operating.input_speed_rpm = 1200;  // [rpm]
  c.operating.input_power_W = 20000;   // [W]
  return c;
}

} // namespace pw::diagnose::test
