// Mesh stiffness of a spur-gear mesh along its line of action (LOA).
//
// Single pair (potential-energy method, docs/stiffness.md §2): the driver's
// tooth (A), the driven tooth (B) and the Hertzian contact act in series,
//   k(xi) = 1 / (c_A(r_A(xi)) + c_B(r_B(xi)) + c_H)            [N/m],
// with xi the roll coordinate of geometry/mesh.hpp (from the driver's base
// tangent point T_A) and r_A, r_B the contact radii on A and B. (The seed's
// Eq. (9), K1 K2 KH / (K1 + K2 + KH), is not a series combination and is not
// dimensionally a stiffness; docs/stiffness.md §4.)
//
// Combined mesh stiffness: the pairs in contact act in parallel; pair n sits at
// xi - n p_b, so k_mesh(xi) = sum_n k(xi + n p_b) over the pairs inside the
// active range [start_active_m, end_active_m], periodic in p_b.
//
// The curve is tabulated once (StiffnessSettings::samples_per_pair points) and
// evaluated in O(1) without allocation, so the dynamics may call it every step.
#pragma once

#include "config/stage.hpp"
#include "geometry/gear.hpp"
#include "geometry/mesh.hpp"
#include "stiffness/tooth_compliance.hpp"

#include <vector>

namespace pw::stiffness {

/// Single-pair stiffness over one pair's contact, sampled uniformly in xi.
/// A plain value type: xi_m[i] = start + i (end - start) / (n - 1), n >= 2.
struct PairStiffnessCurve {
  std::vector<double> xi_m;   ///< roll coordinate [m], uniform, ascending
  std::vector<double> k_N_m;  ///< single-pair stiffness [N/m]

  /// Linear interpolation in the table; 0 outside [xi_m.front(), xi_m.back()]
  /// (no pair in contact). O(1): the index follows from the uniform spacing.
  double operator()(double xi) const {
    const std::size_t n = xi_m.size();
    if (n < 2) return 0.0;
    const double x0 = xi_m.front();
    const double x1 = xi_m.back();
    if (!(xi >= x0 && xi <= x1)) return 0.0;
    const double u = (xi - x0) / (x1 - x0) * static_cast<double>(n - 1);
    std::size_t i = static_cast<std::size_t>(u);
    if (i > n - 2) i = n - 2;
    const double f = u - static_cast<double>(i);
    return k_N_m[i] + f * (k_N_m[i + 1] - k_N_m[i]);
  }
};

/// Model choices below StiffnessSettings (which the TOML file sets).
struct MeshStiffnessOptions {
  ElasticState elastic_state = ElasticState::PlaneStrain;  ///< docs/stiffness.md §1.4
  int quadrature_points = 24;  ///< per beam segment; 24 converges to < 1e-12 (tests/stiffness)
  /// r_int / r_f of the external gears' bodies (model::StageSpec::bore_ratio):
  /// Sainsot's h_f = 1 / bore_ratio.
  double bore_ratio = 0.3;
  /// Sainsot h_f used for the ring's body: 1.4, the thin-body end of the fit,
  /// an external body whose depth below the root is about 3.5 m, the ISO
  /// 6336-3 rim depth for which an internal gear's rim counts as solid
  /// (docs/stiffness.md §1.5; the seed gives no rim geometry).
  double ring_body_ratio = 1.4;
};

/// Compliances of one tooth pair at one roll position [m/N].
struct PairCompliance {
  ToothCompliance a;       ///< driver's tooth
  ToothCompliance b;       ///< driven tooth
  double hertz_m_N = 0;    ///< Yang & Lin 1987
  double total_m_N() const { return a.total_m_N() + b.total_m_N() + hertz_m_N; }
};

/// Both teeth of a mesh, set up once. A is the driver (sun in sun-planet,
/// planet in planet-ring), B the driven member (planet, ring).
class PairStiffnessModel {
public:
  PairStiffnessModel(const geometry::MeshGeometry& mesh, const geometry::GearSpec& a, const geometry::GearSpec& b,
                     bool include_fillet_foundation = true, const MeshStiffnessOptions& options = {});
  /// Compliance parts at roll coordinate xi in [start_active_m, end_active_m].
  PairCompliance compliance(double xi_m) const;
  /// Unscaled single-pair stiffness 1 / total [N/m].
  double stiffness(double xi_m) const { return 1.0 / compliance(xi_m).total_m_N(); }
  const ToothModel& tooth_a() const { return a_; }
  const ToothModel& tooth_b() const { return b_; }
  const geometry::MeshGeometry& mesh() const { return mesh_; }

private:
  geometry::MeshGeometry mesh_;
  ToothModel a_, b_;
  double hertz_ = 0;
};

/// Tabulates the single-pair stiffness over [start_active_m, end_active_m] at
/// settings.samples_per_pair points, times settings.scale, with or without
/// the fillet-foundation term (settings.include_fillet_foundation). Throws
/// pw::InputError naming "samples_per_pair" (< 2) or "scale" (<= 0).
PairStiffnessCurve single_pair_stiffness(const geometry::MeshGeometry& mesh, const geometry::GearSpec& a,
                                         const geometry::GearSpec& b, const model::StiffnessSettings& settings,
                                         const MeshStiffnessOptions& options = {});

/// Combined (all pairs in parallel) stiffness at roll coordinate xi [N/m]:
/// sum of curve(xi + n p_b) over integers n. Periodic in p_b. O(contact ratio).
/// ramp_half_width_m > 0: each pair's stiffness ramps linearly over +-ramp_half_width_m about
/// the ends of the active path (geometry::engagement_weight, contact.engagement_ramp).
double combined_stiffness(const PairStiffnessCurve& curve, const geometry::MeshGeometry& mesh, double xi_m,
                          double ramp_half_width_m = 0.0);

/// The seed's Table 2 quantities for one mesh.
struct MeshStiffnessSummary {
  double max_single_pair_N_m = 0;  ///< max of the single-pair curve
  double combined_max_N_m = 0;     ///< "max. general stiffness"
  double combined_min_N_m = 0;
  double combined_mean_N_m = 0;
  /// Amplitude of the first harmonic (mesh frequency) of the combined
  /// stiffness over one mesh period: (2/M) |sum_j k_j exp(-2 pi i j / M)|
  /// (the seed's "first stiffness excitation").
  double first_harmonic_N_m = 0;
};

/// Samples the combined stiffness at `samples` uniform points over one mesh
/// period [start_active_m, start_active_m + p_b) and reduces them.
MeshStiffnessSummary summarize(const PairStiffnessCurve& curve, const geometry::MeshGeometry& mesh,
                               int samples = 4096);

} // namespace pw::stiffness
