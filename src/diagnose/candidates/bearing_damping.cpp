// Rig element: the damping of the bearings and supports (bearings.damping_ratio) of the
// lateral-torsional model. Lin & Parker's model, and this one by default, holds the sun, ring,
// carrier and planets on undamped springs: the only dissipation is the meshes'. A real
// bearing dissipates (rolling-element bearings: damping ratios of a few per cent; film
// bearings more), and a mode dominated by a bearing then rings far less than the model's.
// Measured on the second independent simulator's rig (Rayleigh damping on every coordinate):
// with undamped supports a planet-tooth fault's sidebands near the bearing-dominated modes at
// 2-2.6 kHz came out 20-60 times the recording's, and the severity fit stopped at a tenth of
// the true loss (docs/diagnose-log.md, session 41).
//
// One parameter, the damping ratio zeta of every support (c = 2 zeta sqrt(k m), model/
// lumped_model.cpp), on a linear scale from 0 (undamped, the default) to kUpper. 'Absent' is
// the configured value. The screening value is kTypical, the middle of the range quoted for
// rolling-element bearings (twice the configured ratio when one is set). The torsional model
// has no bearings: there it does not act.
#include "diagnose/candidates/factories.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {

/// Upper end of the box [-]: half of critical, beyond any bearing's (squeeze-film dampers reach
/// 0.2-0.3); a fit that wants more than this is told so by the bound.
constexpr double kUpper = 0.5;
/// A rolling-element bearing's damping ratio [-], the screening step and the fit's start.
constexpr double kTypical = 0.05;

class BearingDamping final : public Candidate {
public:
  std::string name() const override { return "bearing_damping"; }
  std::string physics() const override {
    return "the bearings and supports dissipate: the lateral modes they dominate ring less than the undamped "
           "supports of the model let them";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool rig_design() const override { return true; }
  bool acts_on(const model::SimulationConfig& b) const override {
    return b.solver.level == model::ModelLevel::LateralTorsional;
  }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double configured = b.bearings.damping_ratio;
    const double upper = std::max(kUpper, configured);
    const double start = configured > 0 ? configured : kTypical;
    // The screening step: to a typical bearing from undamped supports, else twice the configured
    // ratio (half the resonant amplification of the modes the bearings dominate), inside the box.
    const double screen = configured > 0 ? std::min(2 * configured, upper) : kTypical;
    return {ParameterSpec{.name = "bearings.damping_ratio", .unit = "1", .lower = 0.0, .upper = upper,
        .log_scale = false, .initial = start, .null_value = configured, .screen_value = screen}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "bearings.damping_ratio", std::max(0.0, x[0]), o);
  }
};

} // namespace
std::unique_ptr<Candidate> bearing_damping() { return std::make_unique<BearingDamping>(); }
} // namespace pw::diagnose::candidates
