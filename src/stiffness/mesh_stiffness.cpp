#include "stiffness/mesh_stiffness.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace pw::stiffness {

using geometry::GearKind;
using geometry::GearSpec;
using geometry::MeshGeometry;

namespace {

ToothModelOptions tooth_options(const GearSpec& g, bool fillet, const MeshStiffnessOptions& o) {
  ToothModelOptions t;
  t.elastic_state = o.elastic_state;
  t.quadrature_points = o.quadrature_points;
  t.include_fillet_foundation = fillet;
  if (g.kind == GearKind::Internal) {
    t.body_ratio = o.ring_body_ratio;
  } else {
    require(o.bore_ratio > 0 && o.bore_ratio < 1, "bore_ratio", "must be in (0, 1), got ", o.bore_ratio);
    t.body_ratio = 1.0 / o.bore_ratio;
  }
  return t;
}

} // namespace

PairStiffnessModel::PairStiffnessModel(const MeshGeometry& mesh, const GearSpec& a, const GearSpec& b,
                                       bool fillet, const MeshStiffnessOptions& o)
    : mesh_(mesh), a_(a, tooth_options(a, fillet, o)), b_(b, tooth_options(b, fillet, o)),
      hertz_(hertz_compliance(a.material, b.material, std::fmin(a.face_width_m, b.face_width_m))) {
  require(a.kind == GearKind::External, "kind", "the driving member of a mesh must be an external gear");
  require(mesh.end_active_m > mesh.start_active_m, "mesh", "empty active range [", mesh.start_active_m, ", ",
          mesh.end_active_m, "] m");
}

PairCompliance PairStiffnessModel::compliance(double xi) const {
  PairCompliance c;
  c.a = a_.compliance(geometry::contact_radius_a(mesh_, xi));
  c.b = b_.compliance(geometry::contact_radius_b(mesh_, xi));
  c.hertz_m_N = hertz_;
  return c;
}

PairStiffnessCurve single_pair_stiffness(const MeshGeometry& mesh, const GearSpec& a, const GearSpec& b,
                                         const model::StiffnessSettings& s, const MeshStiffnessOptions& o) {
  require(s.samples_per_pair >= 2, "stiffness.samples_per_pair", "must be >= 2, got ", s.samples_per_pair);
  require(s.scale > 0 && std::isfinite(s.scale), "stiffness.scale", "must be > 0, got ", s.scale);
  const PairStiffnessModel model(mesh, a, b, s.include_fillet_foundation, o);
  const int n = s.samples_per_pair;
  PairStiffnessCurve curve;
  curve.xi_m.resize(n);
  curve.k_N_m.resize(n);
  const double x0 = mesh.start_active_m;
  const double dx = (mesh.end_active_m - mesh.start_active_m) / (n - 1);
  for (int i = 0; i < n; ++i) {
    // The last node is set exactly so that the table's range is the active range.
    const double xi = i == n - 1 ? mesh.end_active_m : x0 + i * dx;
    curve.xi_m[i] = xi;
    curve.k_N_m[i] = s.scale * model.stiffness(xi);
  }
  return curve;
}

double combined_stiffness(const PairStiffnessCurve& curve, const MeshGeometry& mesh, double xi, double ramp_half_width_m) {
  if (curve.xi_m.size() < 2) return 0.0;
  const double pb = mesh.base_pitch_m;
  if (ramp_half_width_m > 0) {
    // Pairs within the widened window, each weighted by its ramp; the stiffness beyond the
    // table's ends is its end value, as in the simulation (PlanetaryDynamics).
    const double lo = mesh.start_active_m - ramp_half_width_m, hi = mesh.end_active_m + ramp_half_width_m;
    double k = 0.0;
    for (double n = std::ceil((lo - xi) / pb); n <= std::floor((hi - xi) / pb); n += 1.0) {
      const double x = xi + n * pb;
      k += geometry::engagement_weight(mesh, x, ramp_half_width_m) *
           curve(std::clamp(x, curve.xi_m.front(), curve.xi_m.back()));
    }
    return k;
  }
  const double lo = curve.xi_m.front();
  const double hi = curve.xi_m.back();
  // Pairs at xi + n p_b for every integer n with the argument in [lo, hi].
  const double n_lo = std::ceil((lo - xi) / pb - 1e-12);
  const double n_hi = std::floor((hi - xi) / pb + 1e-12);
  double k = 0.0;
  for (double n = n_lo; n <= n_hi; n += 1.0) k += curve(std::clamp(xi + n * pb, lo, hi));
  return k;
}

MeshStiffnessSummary summarize(const PairStiffnessCurve& curve, const MeshGeometry& mesh, int samples) {
  require(samples >= 8, "samples", "must be >= 8, got ", samples);
  MeshStiffnessSummary s;
  if (curve.k_N_m.empty()) return s;
  s.max_single_pair_N_m = *std::max_element(curve.k_N_m.begin(), curve.k_N_m.end());
  s.combined_max_N_m = -1.0;
  s.combined_min_N_m = 1e300;
  std::complex<double> h1{0.0, 0.0};
  double sum = 0.0;
  const double pb = mesh.base_pitch_m;
  const double x0 = curve.xi_m.front();
  for (int j = 0; j < samples; ++j) {
    const double k = combined_stiffness(curve, mesh, x0 + pb * j / samples);
    s.combined_max_N_m = std::max(s.combined_max_N_m, k);
    s.combined_min_N_m = std::min(s.combined_min_N_m, k);
    sum += k;
    h1 += k * std::polar(1.0, -2.0 * std::numbers::pi * j / samples);
  }
  s.combined_mean_N_m = sum / samples;
  s.first_harmonic_N_m = 2.0 * std::abs(h1) / samples;
  return s;
}

} // namespace pw::stiffness
