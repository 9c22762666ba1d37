// Mesh stiffness curves (stiffness/mesh_stiffness.hpp): the tabulated
// single-pair curve, the combined stiffness built from it, the summary
// against a closed-form Fourier series, the settings (scale, fillet), an
// independent reference value, and the no-allocation contract of evaluation.
#include "stiffness/mesh_stiffness.hpp"

#include "config/stage.hpp"
#include "core/error.hpp"
#include "geometry/mesh.hpp"
#include "stiffness/iso6336.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <numbers>

using namespace pw;
using namespace pw::stiffness;
using geometry::GearSpec;
using geometry::MeshGeometry;

// ---- allocation counter for the "evaluation does not allocate" test --------
namespace {
std::atomic<long> g_allocations{0};
}
void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

struct SeedMeshes {
  model::StageSpec st;
  MeshGeometry sp = geometry::make_mesh(st.sun, st.planet);
  MeshGeometry pr = geometry::make_mesh(st.planet, st.ring);
};

const SeedMeshes& seed() {
  static const SeedMeshes s;
  return s;
}

} // namespace

TEST(PairCurve, InterpolatesTheModelAndIsZeroOutsideTheActiveRange) {
  // Nodes reproduce the model exactly; between nodes linear interpolation of a
  // smooth curve sampled at 200 points is within 1e-4 (relative) of the model
  // (second difference of k over one step is ~1e-5 of k here); outside the
  // active range no pair is in contact, so the stiffness is exactly 0.
  const auto& s = seed();
  const model::StiffnessSettings set;
  for (const bool ring : {false, true}) {
    const MeshGeometry& m = ring ? s.pr : s.sp;
    const GearSpec& a = ring ? s.st.planet : s.st.sun;
    const GearSpec& b = ring ? s.st.ring : s.st.planet;
    const PairStiffnessCurve c = single_pair_stiffness(m, a, b, set);
    const PairStiffnessModel model(m, a, b);
    ASSERT_EQ(c.xi_m.size(), 200u);
    EXPECT_DOUBLE_EQ(c.xi_m.front(), m.start_active_m);
    EXPECT_DOUBLE_EQ(c.xi_m.back(), m.end_active_m);
    for (std::size_t i = 0; i < c.xi_m.size(); i += 37) EXPECT_DOUBLE_EQ(c(c.xi_m[i]), model.stiffness(c.xi_m[i]));
    for (int j = 0; j < 50; ++j) {
      const double xi = m.start_active_m + (m.end_active_m - m.start_active_m) * (j + 0.37) / 50;
      EXPECT_NEAR(c(xi), model.stiffness(xi), 1e-4 * model.stiffness(xi)) << "xi = " << xi;
    }
    EXPECT_EQ(c(m.start_active_m - 1e-9), 0.0);
    EXPECT_EQ(c(m.end_active_m + 1e-9), 0.0);
  }
}

TEST(CombinedStiffness, IsPeriodicInTheBasePitch) {
  // k_mesh(xi + p_b) = k_mesh(xi): the same set of tooth positions repeats.
  // Tolerance 1e-9 relative: only the floating-point position of the samples
  // changes (a shifted argument may fall on the other side of a node).
  const auto& s = seed();
  const PairStiffnessCurve c = single_pair_stiffness(s.sp, s.st.sun, s.st.planet, {});
  const double pb = s.sp.base_pitch_m;
  for (int j = 0; j < 97; ++j) {
    const double xi = s.sp.start_active_m + pb * (j + 0.5) / 97;
    const double k0 = combined_stiffness(c, s.sp, xi);
    EXPECT_NEAR(combined_stiffness(c, s.sp, xi + pb), k0, 1e-9 * k0);
    EXPECT_NEAR(combined_stiffness(c, s.sp, xi - 3 * pb), k0, 1e-9 * k0);
  }
}

TEST(CombinedStiffness, IsContinuousExceptWhereAPairEntersOrLeaves) {
  // The potential-energy mesh stiffness is piecewise continuous: it jumps only
  // where a pair enters (xi = start + n p_b) or leaves (xi = end + n p_b), and
  // there by exactly the single-pair stiffness at that end. Elsewhere the step
  // between neighbouring samples (dxi = p_b/4000) is below 0.2 % of k (the
  // steepest single-pair slope is ~50 % of k per mm).
  const auto& s = seed();
  for (const bool ring : {false, true}) {
    const MeshGeometry& m = ring ? s.pr : s.sp;
    const PairStiffnessCurve c =
        single_pair_stiffness(m, ring ? s.st.planet : s.st.sun, ring ? s.st.ring : s.st.planet, {});
    const double pb = m.base_pitch_m;
    const int n = 4000;
    const double dxi = pb / n;
    const auto near_event = [&](double xi) {
      for (double e : {m.start_active_m, m.end_active_m}) {
        const double d = std::remainder(xi - e, pb);
        if (std::fabs(d) < 1.5 * dxi) return true;
      }
      return false;
    };
    int events = 0;
    for (int j = 0; j < n; ++j) {
      const double x0 = m.start_active_m + 0.3 * dxi + j * dxi;
      const double k0 = combined_stiffness(c, m, x0), k1 = combined_stiffness(c, m, x0 + dxi);
      if (near_event(x0 + 0.5 * dxi)) {
        ++events;
        continue;
      }
      EXPECT_LT(std::fabs(k1 - k0), 2e-3 * k0) << (ring ? "planet-ring" : "sun-planet") << " at xi = " << x0;
    }
    EXPECT_GE(events, 2);  // one entry and one exit per period
    // The jump at entry equals the entering pair's stiffness.
    const double e = m.start_active_m + pb;
    const double jump = combined_stiffness(c, m, e + 1e-12) - combined_stiffness(c, m, e - 1e-9);
    EXPECT_NEAR(jump, c.k_N_m.front(), 1e-3 * c.k_N_m.front());
  }
}

TEST(Settings, ScaleMultipliesEveryStiffnessAndTheSummary) {
  // StiffnessSettings::scale multiplies the single-pair curve, hence the
  // combined stiffness and every summary number, exactly (round-off only).
  const auto& s = seed();
  model::StiffnessSettings one, scaled;
  scaled.scale = 0.01;
  const PairStiffnessCurve c1 = single_pair_stiffness(s.sp, s.st.sun, s.st.planet, one);
  const PairStiffnessCurve c2 = single_pair_stiffness(s.sp, s.st.sun, s.st.planet, scaled);
  for (std::size_t i = 0; i < c1.k_N_m.size(); ++i) EXPECT_NEAR(c2.k_N_m[i], 0.01 * c1.k_N_m[i], 1e-14 * c1.k_N_m[i]);
  const MeshStiffnessSummary a = summarize(c1, s.sp), b = summarize(c2, s.sp);
  EXPECT_NEAR(b.max_single_pair_N_m, 0.01 * a.max_single_pair_N_m, 1e-12 * a.max_single_pair_N_m);
  EXPECT_NEAR(b.combined_max_N_m, 0.01 * a.combined_max_N_m, 1e-12 * a.combined_max_N_m);
  EXPECT_NEAR(b.combined_mean_N_m, 0.01 * a.combined_mean_N_m, 1e-12 * a.combined_mean_N_m);
  EXPECT_NEAR(b.first_harmonic_N_m, 0.01 * a.first_harmonic_N_m, 1e-12 * a.first_harmonic_N_m);
  scaled.scale = 0.0;
  EXPECT_THROW((void)single_pair_stiffness(s.sp, s.st.sun, s.st.planet, scaled), InputError);
  scaled.scale = 1.0;
  scaled.samples_per_pair = 1;
  EXPECT_THROW((void)single_pair_stiffness(s.sp, s.st.sun, s.st.planet, scaled), InputError);
}

TEST(Settings, FilletFoundationTermMakesEveryPairSofter) {
  // Dropping the Sainsot body term removes a positive compliance everywhere.
  const auto& s = seed();
  model::StiffnessSettings with, without;
  without.include_fillet_foundation = false;
  const PairStiffnessCurve a = single_pair_stiffness(s.pr, s.st.planet, s.st.ring, with);
  const PairStiffnessCurve b = single_pair_stiffness(s.pr, s.st.planet, s.st.ring, without);
  for (std::size_t i = 0; i < a.k_N_m.size(); ++i) EXPECT_LT(a.k_N_m[i], b.k_N_m[i]);
}

namespace {
/// A constant single-pair stiffness k0 over a path of eps = 1.62 base pitches (p_b 8 mm).
struct ConstantPair {
  double eps = 1.62, k0 = 3e8;
  MeshGeometry mesh;
  PairStiffnessCurve curve;
  ConstantPair() {
    mesh.base_pitch_m = 8e-3;
    mesh.start_active_m = 2e-3;
    mesh.end_active_m = mesh.start_active_m + eps * mesh.base_pitch_m;
    for (int i = 0; i < 11; ++i) {
      curve.xi_m.push_back(mesh.start_active_m + (mesh.end_active_m - mesh.start_active_m) * i / 10);
      curve.k_N_m.push_back(k0);
    }
    curve.xi_m.back() = mesh.end_active_m;
  }
};
} // namespace

TEST(Summary, RectangularWaveMatchesItsFourierSeries) {
  // A constant single-pair stiffness k0 over a contact of eps base pitches
  // gives a combined stiffness that is a rectangular wave between
  // floor(eps) k0 and ceil(eps) k0, high for a fraction d = eps - floor(eps)
  // of the period: mean eps k0, first-harmonic amplitude (2 k0/pi) sin(pi d).
  // 4096 samples resolve the edges to 1/4096 of a period: tolerance 1e-3.
  const ConstantPair p;
  const MeshGeometry& m = p.mesh;
  const PairStiffnessCurve& c = p.curve;
  const double eps = p.eps, k0 = p.k0;
  const MeshStiffnessSummary sm = summarize(c, m);
  const double d = eps - 1;
  EXPECT_DOUBLE_EQ(sm.max_single_pair_N_m, k0);
  EXPECT_NEAR(sm.combined_max_N_m, 2 * k0, 1e-9 * k0);
  EXPECT_NEAR(sm.combined_min_N_m, k0, 1e-9 * k0);
  EXPECT_NEAR(sm.combined_mean_N_m, eps * k0, 1e-3 * k0);
  EXPECT_NEAR(sm.first_harmonic_N_m, 2 * k0 / std::numbers::pi * std::sin(std::numbers::pi * d), 1e-3 * k0);
}

namespace {
/// Amplitude of harmonic h of the combined stiffness over one base pitch, M samples (DFT).
double combined_harmonic(const PairStiffnessCurve& c, const MeshGeometry& m, int h, double ramp_half_width_m, int M) {
  double re = 0, im = 0;
  for (int j = 0; j < M; ++j) {
    const double k = combined_stiffness(c, m, m.start_active_m + m.base_pitch_m * j / M, ramp_half_width_m);
    const double ph = 2 * std::numbers::pi * h * j / M;
    re += k * std::cos(ph);
    im -= k * std::sin(ph);
  }
  return (h == 0 ? 1.0 : 2.0) * std::hypot(re, im) / M;
}
} // namespace

TEST(EngagementRamp, AttenuatesEachHarmonicOfAConstantPairsRectangularWaveBySincOfItsWidth) {
  // A linear ramp of full width r p_b centred on each end of the path is the box average of the
  // sharp indicator over r p_b (while 2h < the path), so for a constant pair stiffness k0 the
  // combined stiffness is the rectangular wave of Summary.RectangularWave... averaged over r p_b:
  // its n-th harmonic is (2 k0 / (pi n)) |sin(pi n d)| |sinc(n r)|, sinc(x) = sin(pi x)/(pi x),
  // and its mean stays eps k0. The ramped wave is continuous and piecewise linear, so 8192
  // samples leave an aliasing error of order k0 (n / M)^2 / r < 1e-6 k0 for n <= 12.
  const ConstantPair p;
  const MeshGeometry& m = p.mesh;
  const PairStiffnessCurve& c = p.curve;
  const double eps = p.eps, d = eps - 1, k0 = p.k0;
  constexpr int M = 8192;
  for (const double r : {0.05, 0.2, 0.5}) {
    const double h = 0.5 * r * m.base_pitch_m;
    EXPECT_NEAR(combined_harmonic(c, m, 0, h, M), eps * k0, 1e-6 * k0) << "r " << r;
    for (int n = 1; n <= 12; ++n) {
      const double x = std::numbers::pi * n * r;
      const double expected = 2 * k0 / (std::numbers::pi * n) * std::fabs(std::sin(std::numbers::pi * n * d)) *
                              std::fabs(std::sin(x) / x);
      EXPECT_NEAR(combined_harmonic(c, m, n, h, M), expected, 1e-6 * k0) << "r " << r << ", harmonic " << n;
    }
  }
}

TEST(EngagementRamp, KeepsTheSeedMeshesMeanStiffnessToSecondOrderInItsWidth) {
  // A centred linear ramp moves stiffness from inside the path to just outside it. At each end
  // the moved stiffness is weighted by (1 - w)(x) - w(-x) about the end: odd, so with the
  // stiffness constant outside and linear (slope k') inside the mean moves by k' h^2 / 12 per
  // end and period, |dk_mean| <= 2 max|k'| h^2 / (12 p_b). The sharp mean's own sampling error
  // is at most (its two jumps) / M: both bound the difference.
  const auto& s = seed();
  const model::StiffnessSettings set;
  for (const bool ring : {false, true}) {
    const MeshGeometry& m = ring ? s.pr : s.sp;
    const PairStiffnessCurve c =
        ring ? single_pair_stiffness(m, s.st.planet, s.st.ring, set) : single_pair_stiffness(m, s.st.sun, s.st.planet, set);
    double slope = 0, jump = 0;
    for (std::size_t i = 1; i < c.xi_m.size(); ++i)
      slope = std::max(slope, std::fabs((c.k_N_m[i] - c.k_N_m[i - 1]) / (c.xi_m[i] - c.xi_m[i - 1])));
    jump = c.k_N_m.front() + c.k_N_m.back();
    constexpr int M = 20000;
    const double sharp = combined_harmonic(c, m, 0, 0.0, M);
    for (const double r : {0.1, 0.3}) {
      const double h = 0.5 * r * m.base_pitch_m;
      const double bound = 2 * slope * h * h / (12 * m.base_pitch_m) + jump / M;
      const double ramped = combined_harmonic(c, m, 0, h, M);
      EXPECT_LE(std::fabs(ramped - sharp), bound) << (ring ? "planet-ring" : "sun-planet") << ", r " << r;
      // and it is not trivially equal: the ramp did change the wave
      EXPECT_GT(std::fabs(combined_harmonic(c, m, 8, h, M) - combined_harmonic(c, m, 8, 0.0, M)), 1e-3 * sharp);
    }
  }
}

TEST(PairCurve, EvaluationAllocatesNothing) {
  // The dynamics evaluates the curve every time step: no heap traffic there.
  const auto& s = seed();
  const PairStiffnessCurve c = single_pair_stiffness(s.sp, s.st.sun, s.st.planet, {});
  double sum = 0;
  const long before = g_allocations.load();
  for (int j = 0; j < 10000; ++j) {
    const double xi = s.sp.start_active_m + 1e-6 * j;
    sum += c(xi) + combined_stiffness(c, s.sp, xi);
  }
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_GT(sum, 0);
}

TEST(Reference, SeedStageSinglePairAndMeanStiffnessLieWithinTwentyFivePercentOfIso6336) {
  // ISO 6336-1 c' is the maximum single-pair stiffness and c_gamma_alpha the
  // mean mesh stiffness per face width (method B). Why +-25 %: ISO's c' is
  // itself its theory (c'_th, Weber/Banaschek plane-strain solid discs) times
  // the empirical C_M = 0.8, i.e. theory and measurement already differ by
  // 20 %; PE models differ from FE by about 5-15 % at the pitch point (see the
  // Reference test below and docs/stiffness.md §3). A correct PE model must
  // therefore land within 25 % of c' and c_gamma_alpha, and a unit slip (x10)
  // or a missing/duplicated tooth compliance (x0.5 to x2) falls outside.
  const auto& s = seed();
  for (const bool ring : {false, true}) {
    const MeshGeometry& m = ring ? s.pr : s.sp;
    const GearSpec& a = ring ? s.st.planet : s.st.sun;
    const GearSpec& b = ring ? s.st.ring : s.st.planet;
    const MeshStiffnessSummary sm = summarize(single_pair_stiffness(m, a, b, {}), m);
    const IsoMeshStiffness iso = iso6336_stiffness(a, b, m.contact_ratio);
    const double r1 = sm.max_single_pair_N_m / iso.c_prime_N_m;
    const double r2 = sm.combined_mean_N_m / iso.c_gamma_alpha_N_m;
    std::printf("[ ISO    ] %s: PE max single %.4e / ISO c' %.4e = %.3f; PE mean %.4e / ISO c_ga %.4e = %.3f\n",
                ring ? "planet-ring" : "sun-planet", sm.max_single_pair_N_m, iso.c_prime_N_m, r1,
                sm.combined_mean_N_m, iso.c_gamma_alpha_N_m, r2);
    std::printf("[ ISO    ]   combined max %.4e min %.4e, first harmonic %.4e N/m; ISO c'_th b %.4e N/m\n",
                sm.combined_max_N_m, sm.combined_min_N_m, sm.first_harmonic_N_m, iso.c_th_N_mm_um * 1e3 * a.face_width_m * 1e6);
    const PairCompliance pc = PairStiffnessModel(m, a, b).compliance(m.pitch_point_m);
    std::printf("[ ISO    ]   pitch point [m/N]: A bend %.3e shear %.3e axial %.3e fillet %.3e | B bend %.3e shear %.3e "
                "axial %.3e fillet %.3e | Hertz %.3e\n",
                pc.a.bending_m_N, pc.a.shear_m_N, pc.a.axial_m_N, pc.a.fillet_m_N, pc.b.bending_m_N, pc.b.shear_m_N,
                pc.b.axial_m_N, pc.b.fillet_m_N, pc.hertz_m_N);
    EXPECT_GT(r1, 0.75);
    EXPECT_LT(r1, 1.25);
    EXPECT_GT(r2, 0.75);
    EXPECT_LT(r2, 1.25);
  }
}

TEST(Reference, Pair17To43PitchPointStiffnessAgreesWithPlaneStrainFeWithinFifteenPercent) {
  // Reference value: single-pair stiffness at the pitch point of a fully
  // specified spur pair, from an independent 2-D plane-strain finite-element
  // model of the generated teeth (9-node quadrilaterals, whole gear as a
  // periodic ring, bore r_f/1.4 clamped; mesh-converged to 0.06 %, checked
  // against Hertz and a Timoshenko cantilever), reported in a public design
  // note ("Unified contact model: phase-exact prototype", section 2.4 "Tooth
  // stiffness") as c' = 17.06 N/(mm um) (its ISO 6336-1 c'_th: 16.03).
  // NOT a peer-reviewed value: no peer-reviewed PE value with complete gear
  // data could be retrieved in this session (docs/stiffness.md §3).
  // Pair data: z 17 / 43, m 1 mm, alpha 20 deg, x 0, h_a* 1, h_f* 1.25,
  // rho_f* 0.38, b 10 mm, E 206 GPa, nu 0.3, body h_f = r_f/r_int = 1.4.
  // Tolerance 15 %: the PE beam + Sainsot + Yang-Lin pair model neglects the
  // local contact deformation near the load (FE's contact compliance is
  // larger than Yang & Lin's) and over-estimates the tooth compliance; the
  // two errors partly cancel (the same note's own analytical tooth is 9 %
  // below FE, ISO's c'_th 6 % below).
  GearSpec a{17}, b{43};
  for (GearSpec* g : {&a, &b}) {
    g->module_m = 1e-3;
    g->face_width_m = 10e-3;
    g->pressure_angle_rad = 20 * std::numbers::pi / 180;
    g->material.youngs_modulus_Pa = 206e9;
    g->material.poisson_ratio = 0.3;
    g->material.shear_modulus_Pa = 206e9 / 2.6;
  }
  // z 17 is at the rack-undercut limit (z_min = 17.1 for this rack); the
  // pitch-point stiffness needs only the line of action, written out here for
  // the standard centre distance.
  const geometry::GearGeometry ga = geometry::make_geometry(a), gb = geometry::make_geometry(b);
  MeshGeometry m;
  m.centre_distance_m = ga.reference_radius_m + gb.reference_radius_m;
  m.working_pressure_angle_rad = a.pressure_angle_rad;
  m.base_pitch_m = ga.base_pitch_m;
  m.base_radius_a_m = ga.base_radius_m;
  m.base_radius_b_m = gb.base_radius_m;
  m.tangent_distance_m = m.centre_distance_m * std::sin(m.working_pressure_angle_rad);
  m.pitch_point_m = ga.base_radius_m * std::tan(m.working_pressure_angle_rad);
  m.end_active_m = std::sqrt(ga.tip_radius_m * ga.tip_radius_m - ga.base_radius_m * ga.base_radius_m);
  m.start_active_m = m.tangent_distance_m - std::sqrt(gb.tip_radius_m * gb.tip_radius_m - gb.base_radius_m * gb.base_radius_m);
  m.contact_ratio = (m.end_active_m - m.start_active_m) / m.base_pitch_m;
  MeshStiffnessOptions o;
  o.bore_ratio = 1 / 1.4;
  const PairStiffnessModel model(m, a, b, true, o);
  const double c_prime = model.stiffness(m.pitch_point_m) / (10.0 * 1e6);  // N/m -> N/(mm um) for b = 10 mm
  std::printf("[ REF    ] z17/z43 pitch-point single-pair stiffness %.3f N/(mm um) (FE 17.06, ISO c'_th 16.03)\n",
              c_prime);
  EXPECT_NEAR(c_prime, 17.06, 0.15 * 17.06);
}
