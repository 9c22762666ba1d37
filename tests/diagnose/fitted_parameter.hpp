// A FittedParameter built in one line, for tests of the verdict, the baseline's limits and the
// level checks (they read names, values, errors, boxes and flags, never a fit).
#pragma once

#include "diagnose/diagnose.hpp"

#include <string>

namespace pw::diagnose::test {

/// A dimensionless parameter `name` = value ± se in [lower, upper], started at `initial`.
inline FittedParameter parameter(const std::string& name, double value, double se, double lower, double upper,
                                 double initial, bool nuisance) {
  FittedParameter p;
  p.name = name;
  p.unit = "1";
  p.value = value;
  p.std_error = se;
  p.lower = lower;
  p.upper = upper;
  p.initial = initial;
  p.nuisance = nuisance;
  return p;
}

} // namespace pw::diagnose::test
