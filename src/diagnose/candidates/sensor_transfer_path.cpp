// Transfer path of a housing accelerometer (sensor.window_width_rad): how
// wide the planet-pass window is. Its gain is a nuisance profiled in closed
// form in every comparison (compare.hpp); this candidate changes only the
// housing channels, so it needs no new simulation.
#include "diagnose/candidates/factories.hpp"

namespace pw::diagnose::candidates {
namespace {
class SensorTransferPath final : public Candidate {
public:
  std::string name() const override { return "sensor_transfer_path"; }
  std::string physics() const override {
    return "the housing accelerometer's transfer path is narrower or wider than assumed: each planet is heard "
           "over a different arc of its pass, which reshapes the planet-pass sidebands at k f_m +- j N f_c";
  }
  std::vector<Component> families() const override { return {Component::Carrier}; }
  bool sensor_only() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    return {ParameterSpec{.name = "sensor.window_width_rad", .unit = "rad", .lower = 0.1, .upper = 1.25,
        .log_scale = true, .initial = b.sensor.window_width_rad, .null_value = b.sensor.window_width_rad,
        .screen_value = 1.3 * b.sensor.window_width_rad}};
  }
  /// The ring body's reading (sensor.housing_path = ring_body, model/sensor.hpp Eq. S3) has no
  /// window: its width changes nothing there, and a fit of it would be flat.
  bool acts_on(const model::SimulationConfig& b) const override {
    return b.sensor.housing_path != model::HousingPath::RingBody;
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "sensor.window_width_rad", x[0], o);
  }
};
} // namespace
std::unique_ptr<Candidate> sensor_transfer_path() { return std::make_unique<SensorTransferPath>(); }
} // namespace pw::diagnose::candidates
