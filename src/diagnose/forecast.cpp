#include "diagnose/forecast.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pw::diagnose {

long lm_simulations(std::size_t parameters, int iterations) {
  return 1 + static_cast<long>(std::max(0, iterations)) * (static_cast<long>(parameters) + 1);
}

void SimulationForecast::expect(int step, long simulations) {
  require(step >= 1 && step <= kSteps, "step", "must be in [1, ", kSteps, "], got ", step);
  expected_[static_cast<std::size_t>(step)] = std::max(0L, simulations);
}

void SimulationForecast::begin(int step) {
  require(step >= 1 && step <= kSteps, "step", "must be in [1, ", kSteps, "], got ", step);
  current_ = std::max(current_, step);
}

long SimulationForecast::remaining(long done_in_step) const {
  // The current step's estimate less what it has run already (never below zero: it may run
  // more than expected, and then nothing more of it is forecast).
  long r = std::max(0L, expected_[static_cast<std::size_t>(current_)] - std::max(0L, done_in_step));
  for (int s = current_ + 1; s <= kSteps; ++s) r += expected_[static_cast<std::size_t>(s)];
  return r;
}

SimulationForecast::Estimate SimulationForecast::estimate(long done, long done_in_step, double wall_s) const {
  Estimate e;
  if (done <= 0 || !(wall_s > 0)) return e;
  const long left = remaining(done_in_step);
  e.known = true;
  e.percent = 100.0 * static_cast<double>(done) / static_cast<double>(done + left);
  e.seconds_left = wall_s / static_cast<double>(done) * static_cast<double>(left);
  return e;
}

std::string to_string(const SimulationForecast::Estimate& e) {
  if (!e.known) return "";
  char buf[64];
  const long s = std::lround(e.seconds_left);
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0f %%, ETA %ld s", std::floor(e.percent), s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%.0f %%, ETA %ld min %02ld s", std::floor(e.percent), s / 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%.0f %%, ETA %ld h %02ld min", std::floor(e.percent), s / 3600, (s % 3600) / 60);
  return buf;
}

} // namespace pw::diagnose
