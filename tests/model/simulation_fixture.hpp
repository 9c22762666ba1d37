// Shared by the model tests that run model::simulate on the seed stage: a short
// 400 rpm configuration and lookups into a SimulationResult.
#pragma once

#include "model/simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace pw::test {

/// The seed stage at 400 rpm (short mesh period) recording `record_cycles` mesh periods.
inline model::SimulationConfig fast_seed(int record_cycles = 6) {
  model::SimulationConfig c;
  c.operating.input_speed_rpm = 400;
  c.solver.record_mesh_cycles = record_cycles;
  return c;
}

/// A scalar result by name (a test failure and NaN if absent).
inline double scalar(const model::SimulationResult& r, const std::string& name) {
  for (const auto& s : r.scalars)
    if (s.name == name) return s.value;
  ADD_FAILURE() << "no scalar " << name;
  return NAN;
}

/// A time-history channel by name; throws if absent.
inline const std::vector<double>& channel(const model::SimulationResult& r, const std::string& name) {
  const model::Channel* c = r.find(name);
  if (!c) throw std::runtime_error("no channel " + name);
  return c->values;
}

inline double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

} // namespace pw::test
