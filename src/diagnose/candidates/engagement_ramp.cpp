// Gear-design element: the width of the ramp over which each tooth pair takes and sheds its
// stiffness at the ends of its path of contact (contact.engagement_ramp, model/
// planetary_system.cpp set_engagement_smoothing). The model's involute pairs engage at a
// point; real pairs do not (a rounded or chamfered tip edge, extended contact under load),
// and a rig's documentation rarely says how their tips are finished. A ramp of width r p_b
// averages the pair stiffness over r p_b: the mean and the first harmonics stay, the n-th
// mesh harmonic's excitation falls by about sinc(n r). When the rig's pairs engage more
// gradually than the model's, every line from the fifth or so mesh harmonic up is
// over-predicted in every channel, which no stiffness level, damping or encoder bandwidth
// reproduces across the channels at once. Unlike tip_relief, the ramp does not depend on
// the load and does not change the static transmission error's first harmonics.
//
// Calibration only (`calibrate --rig-elements engagement_ramp`), then applied as calibrated in
// every diagnosis that uses the calibration: it describes the healthy gears' tips, which no
// fault of the library changes, and as a screened finding it would compete with friction and
// tip relief for the same mesh lines on every recording made without a calibration.
//
// 'Absent' is the configured ramp (0 by default: the model's sharp entry). The upper end is
// the configuration's, half a base pitch (stage.hpp kMaxEngagementRamp), or less for gears whose
// contact ratio leaves less room (model::largest_engagement_ramp). The screening value
// 0.1 p_b halves (0.64) the fifth harmonic's excitation and removes the tenth's: a change a
// healthy recording's mesh harmonics show at any speed whose tenth harmonic is analysed.
#include "diagnose/candidates/factories.hpp"

#include "model/simulation.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {

constexpr double kScreen = 0.1;
/// The start scan's spacing [-]. chi2 is not quadratic in the ramp: the n-th harmonic's
/// excitation goes as sinc(n r), whose lobes are 1/n wide in r, so a local fit from one start
/// stops in the lobe it starts in (measured on a synthetic recording with r = 0.2: 0.115, the
/// stiffness level pushed to its bound). 0.025 puts a scan point in every lobe of harmonics up
/// to the 20th; above it sinc(n r) < 1/(pi n r) is below 0.064 for any r >= 0.025 already.
constexpr double kScanStep = 0.025;

class EngagementRamp final : public Candidate {
public:
  std::string name() const override { return "engagement_ramp"; }
  std::string physics() const override {
    return "the tooth pairs take and shed their stiffness over a ramp the configuration lacks (rounded tip "
           "edges, extended contact): the higher mesh harmonics fall off faster than sharply engaging "
           "involutes' do";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool calibration_only() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    // The box ends where the simulation would refuse the ramp (a contact ratio of 2.5 or more
    // leaves less than half a base pitch): a fit never reaches a value prepare() rejects.
    const double upper = std::max(model::largest_engagement_ramp(b), b.contact.engagement_ramp);
    const double absent = b.contact.engagement_ramp;
    // Inside the box and apart from 'absent' (the screening's secant divides by the difference).
    const double screen = absent + kScreen <= upper ? absent + kScreen
                          : upper > absent         ? 0.5 * (absent + upper)
                                                   : 0.5 * absent;
    return {ParameterSpec{.name = "contact.engagement_ramp", .unit = "1", .lower = 0.0, .upper = upper,
        .log_scale = false, .initial = screen, .null_value = absent, .screen_value = screen,
        .scan_at_start = true, .scan_step = kScanStep}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "contact.engagement_ramp", x[0], o);
  }
};

} // namespace
std::unique_ptr<Candidate> engagement_ramp() { return std::make_unique<EngagementRamp>(); }
} // namespace pw::diagnose::candidates
