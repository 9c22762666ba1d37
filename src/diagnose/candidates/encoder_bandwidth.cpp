// Rig element: the speed encoders' bandwidth (sensor.encoder_bandwidth_Hz). A
// speed channel measured by an encoder is a filtered speed: the finite line
// count, the counter's gate time and its smoothing filter act as a low-pass
// (model/sensor.hpp, ButterworthFilter). When the rig's documentation is silent on
// it, the speed channels show the mesh harmonics falling off with frequency
// faster than the model's: this candidate names that and fits the -3 dB
// frequency, in the filter order the configuration gives (default 2).
//
// 'Absent' is an ideal encoder. On the fit's log scale the absent end is a
// bandwidth of 1e4 mesh frequencies: there a first-order filter changes the
// 80th mesh harmonic (the most the analysis uses, order_analysis.hpp) by
// (80 / 1e4)^2 / 2 = 3e-5, a second-order one by 2e-9 -- below any noise
// bound -- and beyond the simulation's Nyquist frequency the filter is the
// identity anyway. So the parameter saturates: above some value it is not
// identifiable, and the report gives the smallest bandwidth that fits as well.
// The screening value of two mesh frequencies halves the power of the second
// mesh harmonic (order 2: gain 1/sqrt(2) at f_c).
#include "diagnose/candidates/factories.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {

constexpr double kAbsentInMeshFrequencies = 1e4;
constexpr double kLowestInMeshFrequencies = 0.25;
constexpr double kScreenInMeshFrequencies = 2.0;

/// Mesh frequency of the configured operating point [Hz].
double mesh_frequency_Hz(const model::SimulationConfig& b) {
  return model::mesh_frequency_Hz(b.stage, b.operating.input_speed_rpm);
}

class EncoderBandwidth final : public Candidate {
public:
  std::string name() const override { return "encoder_bandwidth"; }
  std::string physics() const override {
    return "the speed channels come from encoders with a finite bandwidth: their mesh harmonics fall off above "
           "the encoder's cutoff (a low-pass the model's ideal speed lacks)";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool rig_design() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double fm = mesh_frequency_Hz(b);
    const double absent = b.sensor.encoder_bandwidth_Hz > 0 ? b.sensor.encoder_bandwidth_Hz
                                                             : kAbsentInMeshFrequencies * fm;
    const double lower = std::min(kLowestInMeshFrequencies * fm, absent);
    const double upper = std::max(kAbsentInMeshFrequencies * fm, absent);
    const double screen = std::clamp(kScreenInMeshFrequencies * fm, lower, upper);
    // Start from the configured (calibrated) bandwidth when there is one.
    const double start = b.sensor.encoder_bandwidth_Hz > 0 ? absent : screen;
    ParameterSpec p{.name = "sensor.encoder_bandwidth_Hz", .unit = "Hz", .lower = lower, .upper = upper,
        .log_scale = true, .initial = start, .null_value = absent, .screen_value = screen};
    p.saturates = true;
    return {p};
  }
  /// Only speed channels pass through the encoders.
  bool observable_in(const Recording& r) const override {
    return r.find(Quantity::SunSpeed) != nullptr || r.find(Quantity::CarrierSpeed) != nullptr;
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "sensor.encoder_bandwidth_Hz", x[0], o);
  }
};

} // namespace
std::unique_ptr<Candidate> encoder_bandwidth() { return std::make_unique<EncoderBandwidth>(); }
} // namespace pw::diagnose::candidates
