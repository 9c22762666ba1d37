#include "wear/archard.hpp"

#include <cmath>

namespace pw::wear {

double involute_arc_length(double rb, double r1, double r2) { return std::fabs(r2 * r2 - r1 * r1) / (2 * rb); }

double wear_per_pass(double kappa, double w, double vs, double vr) { return kappa * w * std::fabs(vs) / vr; }

} // namespace pw::wear
