// Rig element: the housing's resonance on its mount (sensor.housing_mount_frequency_Hz,
// model/sensor.hpp). The model's housing accelerometer hears the ring-mesh forces through a
// flat gain G, i.e. as a free mass. A housing on a mount of finite stiffness is a mass on a
// spring: below the mount's resonance f_0 it follows the mount's quasi-static deflection and
// its acceleration rises as (f/f_0)^2 with the frequency of the same force. A rig whose
// housing lines grow relative to the model's the higher the mesh harmonic, while the speed
// channels do not, has such a mount; its documentation rarely gives it.
//
// Log scale from 1 Hz ('absent': a mount that soft is flat, to 1e-4, above the lowest line a
// housing channel is analysed at, the mesh frequency minus its sidebands, tens of Hz at least)
// to 20 kHz, the top of what accelerometers on gear housings measure; above the record's
// analysed band every f_0 gives the same (f/f_0)^2 shape, whose level the profiled gain takes
// (the scan's points beyond the model's Nyquist frequency fail and are not taken). Scanned at
// start: chi2 moves a corner through the lines. Step ratio 2: the high-pass's gain changes by
// at most a factor 4 between neighbouring points at any line.
//
// The mount's damping ratio zeta (sensor.housing_mount_damping_ratio) is the second parameter:
// a housing or a ring on its support rings at f_0 with gain 1/(2 zeta) over the flat path, and
// the lines next to f_0 are raised by as much. Measured on indepsim4's setD4 (a ring of 2.1 kg
// on 1e8 N/m supports, a mode near 1.1 kHz with 2 % damping; docs/diagnose-log.md, session 71):
// its healthy housing lines at 5 f_m - f_c and 7 f_m + f_c (968 and 1361 Hz at 600 rpm) stand 64
// and 101 times above planetwear's flat path, the Butterworth mount's (no peak) cannot raise
// both, and a resonant one fitted to the lines by hand took that channel's chi2 from 1.0e6 to
// 9.5e4. Log scale from 1 % (the low end of the modal damping of assembled steel structures,
// bolted housings ringing at 1-5 %: a physical floor, not a value read off a corpus) to 1/sqrt2,
// the Butterworth, which is 'absent' (today's model) unless the configuration states a damping
// ratio. Scanned after the frequency (the frequency's scan at the configured ratio first): chi2
// is far from quadratic in it where a line sits near f_0. Step ratio sqrt2: the peak's gain
// 1/(2 zeta) changes by at most that between neighbouring points.
//
// Calibration only, applied as calibrated by the diagnoses that use the calibration: a
// property of the rig's housing, which no fault of the library changes.
#include "diagnose/candidates/factories.hpp"

#include <algorithm>
#include <numbers>

namespace pw::diagnose::candidates {
namespace {

constexpr double kAbsent_Hz = 1.0;
constexpr double kUpper_Hz = 2e4;
constexpr double kScreen_Hz = 1e3;
constexpr double kScanStepRatio = 2.0;
constexpr double kLowestDampingRatio = 0.01;
constexpr double kDampingScanStepRatio = std::numbers::sqrt2;

class HousingMount final : public Candidate {
public:
  std::string name() const override { return "housing_mount"; }
  std::string physics() const override {
    return "the housing sits on a mount it resonates on: below that resonance its acceleration rises with the "
           "square of the frequency, so the housing accelerometer hears the higher mesh harmonics more strongly "
           "than a flat transfer path";
  }
  std::vector<Component> families() const override { return {Component::Mesh, Component::Carrier}; }
  bool calibration_only() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double configured = b.sensor.housing_mount_frequency_Hz;
    const double absent = configured > 0 ? configured : kAbsent_Hz;
    const double start = configured > 0 ? configured : kScreen_Hz;
    ParameterSpec p{.name = "sensor.housing_mount_frequency_Hz", .unit = "Hz", .lower = kAbsent_Hz,
        .upper = kUpper_Hz, .log_scale = true, .initial = start, .null_value = absent, .screen_value = kScreen_Hz};
    p.scan_at_start = true;
    p.scan_step_ratio = kScanStepRatio;
    const double zeta = b.sensor.housing_mount_damping_ratio;  // today's 1/sqrt2 unless configured
    const double upper_zeta = std::max(model::SensorSettings::kButterworthDampingRatio, zeta);
    const double lower_zeta = std::min(kLowestDampingRatio, zeta);
    ParameterSpec d{.name = "sensor.housing_mount_damping_ratio", .unit = "1", .lower = lower_zeta,
        .upper = upper_zeta, .log_scale = true, .initial = zeta, .null_value = zeta, .screen_value = zeta};
    d.scan_at_start = true;
    d.scan_step_ratio = kDampingScanStepRatio;
    return {p, d};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "sensor.housing_mount_frequency_Hz", x[0], o);
    set_parameter(c, "sensor.housing_mount_damping_ratio", x[1], o);
  }
  /// Only the housing channels pass through the mount.
  bool observable_in(const Recording& r) const override { return r.find(Quantity::HousingAcceleration) != nullptr; }
};

} // namespace
std::unique_ptr<Candidate> housing_mount() { return std::make_unique<HousingMount>(); }
} // namespace pw::diagnose::candidates
