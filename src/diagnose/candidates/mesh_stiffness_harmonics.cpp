// Rig element: the shape of the gears' stiffness law. The model's mesh stiffness is the
// potential-energy law (docs/stiffness.md); a rig's gears follow their own (finite elements,
// ISO 6336-1's parabolic single-pair law, a measured transmission error, a load-dependent
// contact ratio). Two such laws with the same mean and contact ratio differ in their mesh
// harmonics by tens of per cent (docs/diagnose-log.md, session 21: the independent simulator's
// parabolic law against ours, harmonics 2-5 by factors 0.07 to 8), and every response line at a
// mesh harmonic follows its excitation. No level (stiffness.scale) or damping reaches that: it
// is a difference of form, and without this element a calibration leaves it to the
// discrepancy budget, where it hides any fault acting through the same lines.
//
// Parameters: stiffness.<family>_h<n>_{cos,sin} for both mesh families and n = 1..3, the
// Cartesian parts of a correction of the combined stiffness's n-th harmonic relative to its
// mean (config/stage.hpp StiffnessSettings::Harmonics): Cartesian so that 'absent' (zero) has
// no singular phase. Box +-0.25 of the mean per part: the PE law's own first harmonic is
// 0.1-0.35 of the mean for contact ratios 1.2-2, so a quarter of the mean spans from removing
// the largest PE harmonic to doubling it; the configuration allows +-0.5.
//
// Calibration only, and held at its calibrated value in diagnoses: it describes the healthy
// gears, no fault acts on it (a cracked tooth changes one tooth, not every mesh cycle), and its
// 12 parameters would multiply the cost of every fit of every candidate.
#include "diagnose/candidates/factories.hpp"

#include <algorithm>
#include <array>
#include <string>

namespace pw::diagnose::candidates {
namespace {

constexpr double kBoxRelative = 0.25;
/// Screening value (the nuisance start's "present" alternative) [-]: 5 % of the mean in
/// each part, a change a calibration would notice without leaving the PE law's range.
constexpr double kScreenRelative = 0.05;
constexpr int kHarmonics = model::StiffnessSettings::Harmonics::kCount;

struct Part {
  const char* family;
  int harmonic;  // 1-based
  bool sine;
};

std::array<Part, 4 * kHarmonics> parts() {
  std::array<Part, 4 * kHarmonics> p{};
  int i = 0;
  for (const char* family : {"sun_planet", "planet_ring"})
    for (int h = 1; h <= kHarmonics; ++h)
      for (bool sine : {false, true}) p[i++] = Part{family, h, sine};
  return p;
}

std::string key(const Part& p) {
  return std::string("stiffness.") + p.family + "_h" + std::to_string(p.harmonic) + (p.sine ? "_sin" : "_cos");
}

double configured(const model::SimulationConfig& c, const Part& p) {
  const auto& h = std::string(p.family) == "sun_planet" ? c.stiffness.sun_planet_harmonics
                                                          : c.stiffness.planet_ring_harmonics;
  return p.sine ? h.sin[p.harmonic - 1] : h.cos[p.harmonic - 1];
}

class MeshStiffnessHarmonics final : public Candidate {
public:
  std::string name() const override { return "mesh_stiffness_harmonics"; }
  std::string physics() const override {
    return "the gears' stiffness law differs in shape from the potential-energy law: its first mesh "
           "harmonics differ from the model's at the same mean stiffness";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool calibration_only() const override { return true; }
  bool held_after_calibration() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    std::vector<ParameterSpec> out;
    for (const Part& p : parts()) {
      const double x0 = configured(b, p);
      const double lo = std::min(-kBoxRelative, x0), hi = std::max(kBoxRelative, x0);
      out.push_back(ParameterSpec{.name = key(p), .unit = "1", .lower = lo, .upper = hi, .log_scale = false,
          .initial = x0, .null_value = x0, .screen_value = std::clamp(x0 + kScreenRelative, lo, hi)});
    }
    return out;
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    const auto ps = parts();
    for (std::size_t i = 0; i < ps.size(); ++i) set_parameter(c, key(ps[i]), x[i], o);
  }
};

} // namespace
std::unique_ptr<Candidate> mesh_stiffness_harmonics() { return std::make_unique<MeshStiffnessHarmonics>(); }
} // namespace pw::diagnose::candidates
