// Gear-design element: linear tip relief on every gear's tip (contact.tip_relief_m,
// model/simulation.cpp apply_tip_relief). Real gears carry it to soften the
// engagement; a gear set's documentation often gives the macro-geometry only.
// Without it the model's pairs take load at once when they engage, and the
// mesh harmonics far above the first fall off more slowly than a relieved
// gear's: when the rig's gears are relieved and the configuration does not say
// so, every mesh harmonic above the first few is over-predicted. This
// candidate names that and fits the amount (the relief's length stays
// contact.tip_relief_extent: one parameter, the short relief by default).
//
// 'Absent' is the configured amount, or 0.1 um when none is configured (the
// log scale's floor: three orders below the tooth deflection at a light
// 10 N/mm face load with ISO 6336-1's c' ~ 14 N/(mm um), so no pair's load
// changes measurably). The upper end is the deflection of a pair at 1000 N/mm,
// the top of what case-hardened gears carry (ISO 6336-1's c' again: 70 um),
// below half a module. The screening value of 2 um is a pair's deflection at
// about 30 N/mm: it changes the engagement of every lightly loaded case.
#include "diagnose/candidates/factories.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {

constexpr double kAbsent_m = 1e-7;
constexpr double kUpper_m = 7e-5;
constexpr double kScreen_m = 2e-6;

class TipRelief final : public Candidate {
public:
  std::string name() const override { return "tip_relief"; }
  bool every_planet_alike() const override { return true; }
  std::string physics() const override {
    return "the gears carry tip relief the configuration lacks: relieved pairs take and shed their load "
           "gradually, so the higher mesh harmonics fall off faster than the unmodified involutes' do";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  std::optional<FindingClass> finding_class() const override { return tooth_contact_class(); }
  bool rig_design() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double configured = b.contact.tip_relief_m;
    const double absent = configured > 0 ? configured : kAbsent_m;
    const double upper = std::max(absent, std::min(kUpper_m, 0.5 * b.stage.sun.module_m));
    const double screen = configured > 0 ? (1.5 * absent <= upper ? 1.5 * absent : absent / 1.5)
                                         : std::min(kScreen_m, upper);
    const double start = configured > 0 ? configured : screen;
    return {ParameterSpec{.name = "contact.tip_relief_m", .unit = "m", .lower = std::min(kAbsent_m, absent),
        .upper = upper,
        .log_scale = true, .initial = start, .null_value = absent, .screen_value = screen}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "contact.tip_relief_m", x[0], o);
  }
};

} // namespace
std::unique_ptr<Candidate> tip_relief() { return std::make_unique<TipRelief>(); }
} // namespace pw::diagnose::candidates
