// Sun or carrier runout (eccentricity). The carrier's is fitted as the
// Cartesian components (e cos phi, e sin phi) (its direction relative to the
// planets changes the load sharing, so the phase matters; Cartesian: no
// wrap-around, no singular phase at e = 0); the sun's rotates with the sun,
// so its phase changes no amplitude and only e is fitted (phase 0).
#include "diagnose/candidates/factories.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace pw::diagnose::candidates {
namespace {
class Runout final : public Candidate {
public:
  explicit Runout(bool sun) : sun_(sun) {}
  std::string name() const override { return sun_ ? "sun_runout" : "carrier_runout"; }
  std::string physics() const override {
    return sun_ ? "the sun runs eccentric: its centre circles once per sun revolution relative to the carrier, "
                  "modulating every sun-mesh deflection at f_s - f_c"
                : "the carrier is eccentric: the planet centres are displaced by a vector fixed in the carrier, "
                  "which unequalises the load sharing like a pattern of pin errors";
  }
  std::vector<Component> families() const override {
    return sun_ ? std::vector<Component>{Component::Sun} : std::vector<Component>{Component::Carrier, Component::Mesh};
  }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double m = 0.02 * b.stage.sun.module_m;
    if (sun_)  // rotates with the sun: its phase changes no amplitude, only the magnitude is fitted
      return {ParameterSpec{.name = "sun_eccentricity_m", .unit = "m", .lower = 1e-8, .upper = m,
          .log_scale = true, .initial = 0.05 * m, .null_value = 1e-8, .screen_value = 1e-6}};
    return {ParameterSpec{.name = "carrier_eccentricity_x_m", .unit = "m", .lower = -m, .upper = m,
        .log_scale = false, .initial = 0.05 * m, .null_value = 0.0, .screen_value = 1e-6},
        ParameterSpec{.name = "carrier_eccentricity_y_m", .unit = "m", .lower = -m, .upper = m,
        .log_scale = false, .initial = 0.0, .null_value = 0.0, .screen_value = 1e-6}};
  }
  /// Carrier runout from pin errors p_i (p_0 = 0): the eccentricity (x, y) and common offset c
  /// whose tangential pattern -x sin psi_i + y cos psi_i - c fits p_i best (least squares; exact
  /// for three planets).
  std::vector<double> start_from(const std::string& other, std::span<const double> ox,
                                 const model::SimulationConfig& b) const override {
    const auto psi = planet_angles_rad(b);
    if (sun_ || other != "pin_error" || ox.size() + 1 != psi.size() || psi.size() < 3) return {};
    Eigen::MatrixXd A(static_cast<Eigen::Index>(psi.size()), 3);
    Eigen::VectorXd p(static_cast<Eigen::Index>(psi.size()));
    for (std::size_t i = 0; i < psi.size(); ++i) {
      const auto r = static_cast<Eigen::Index>(i);
      A(r, 0) = -std::sin(psi[i]);
      A(r, 1) = std::cos(psi[i]);
      A(r, 2) = -1.0;
      p(r) = i == 0 ? 0.0 : ox[i - 1];
    }
    const Eigen::VectorXd s = A.colPivHouseholderQr().solve(p);
    return {s(0), s(1)};
  }
  std::optional<FindingClass> finding_class() const override {
    if (sun_) return sun_defect_class();  // the sun's runout rotates with the sun: the sun family's lines
    return planet_position_class();
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    const double e = sun_ ? x[0] : std::hypot(x[0], x[1]);
    const double phi = sun_ || e == 0 ? 0.0 : std::atan2(x[1], x[0]);
    const std::string p = sun_ ? "imperfections.sun_eccentricity" : "imperfections.carrier_eccentricity";
    set_parameter(c, p + "_m", e, o);
    set_parameter(c, p + "_phase_rad", phi, o);
  }

private:
  bool sun_;
};
} // namespace
std::unique_ptr<Candidate> sun_runout() { return std::make_unique<Runout>(true); }
std::unique_ptr<Candidate> carrier_runout() { return std::make_unique<Runout>(false); }
} // namespace pw::diagnose::candidates
