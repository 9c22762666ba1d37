// Order-domain features of a recording and of a simulation (docs/diagnose.md §2).
//
// Nothing here depends on the recording's time step, time origin or on how
// long anybody's warm-up took:
//  * the operating speed comes from the recording (encoder channel mean, else
//    the tacho's pulse rate, else the sidecar's nominal speed refined on the
//    strongest mesh harmonic), and the model is simulated at that speed;
//  * every signal is analysed against its own carrier angle (the recording's
//    from the integral of its speed channel, the tacho or the refined nominal
//    speed; the model's from its carrier/angle channel), over windows of R
//    whole carrier revolutions, so a line of carrier order o sits on DFT bin
//    o R whatever the speed;
//  * only amplitudes are compared: |c_k| of the rectangular-window Fourier
//    coefficients c_k = (1/2 pi R) ∫ x(θ) e^{-i k θ / R} dθ. With whole
//    revolutions every line of integer carrier order (mesh harmonics,
//    planet-pass and carrier sidebands: all that a carrier-periodic response
//    contains) falls on one bin with no leakage at all, so its amplitude does
//    not depend on where the window starts. Lines of the sun, planet and
//    input-shaft families are not integer orders; they leak (sinc) and beat
//    with their neighbours, which is why the comparison adds a
//    non-stationarity variance measured between the recording's two halves
//    (compare.hpp).
//  * a recording too short for two halves of whole carrier revolutions is
//    analysed in halves of Q whole mesh cycles (Q a multiple of the sun's
//    period Zs, of lcm(Zs, Zp) when two of those fit): a line of carrier
//    order o sits on bin o Q / Zr, mesh harmonics on bins n Q. Only the
//    families completing whole periods in Q mesh cycles (resolved) are
//    compared; housing channels, whose every line is a carrier-family line
//    (planets passing the sensor), are not (docs/diagnose.md §2 "Short
//    recordings").
//
// Features are the bins ("cells") nearest to the labelled kinematic lines of
// every family (kinematics.hpp) up to max_order: the mesh harmonics k Zr,
// carrier sidebands k Zr ± j (j <= 4 N), sun, planet and input-shaft
// sidebands as far out, and the low orders of each family. Bins not near any
// line measure the noise floor.
#pragma once

#include "config/stage.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/recording.hpp"
#include "model/result.hpp"
#include "model/simulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <optional>
#include <span>
#include <map>
#include <string>
#include <limits>
#include <vector>

namespace pw::diagnose {

/// Mean operating speed of a recording and how it was obtained.
struct SpeedEstimate {
  double input_rpm = 0;       ///< mean input (sun) speed [rpm]
  double relative_std = 0;    ///< standard error of input_rpm / input_rpm
  std::string source;         ///< "sun_speed channel 'w'", "tacho 'tacho'", "sidecar, refined on ..."
};

/// The recording's mean speed (see the file comment for the order of sources).
SpeedEstimate estimate_speed(const Recording& recording, const model::StageSpec& stage);

/// The carrier angle [rad] at every sample, 0 at the first sample, and how it
/// was obtained ("integral of ...", "tacho edges", "constant speed").
std::vector<double> carrier_angle(const Recording& recording, const model::StageSpec& stage,
                                  const SpeedEstimate& speed, std::string* source = nullptr);

/// Centred moving average over `width` samples (fractional; within width/2 of
/// an end the full width shifted inwards, or the whole record when it is
/// shorter than that). Over one mesh period it removes the speed signal's vibration at
/// every mesh harmonic and keeps its slow variations: the angle reference of
/// order tracking must follow the shaft's mean motion, not its vibration,
/// or the strong high-frequency content of an accelerometer intermodulates
/// into every order.
std::vector<double> mesh_period_average(std::span<const double> x, double width);

/// c_k, k = 0 .. max_bin, of x sampled at increasing angles `angle` over
/// [angle_begin, angle_begin + 2 pi R) (R carrier revolutions, not
/// necessarily whole) by the trapezoidal rule (partial end
/// intervals by linear interpolation), after removing the window's mean.
/// Exact (to rounding) for band-limited signals sampled uniformly in time at
/// constant speed. Throws pw::InputError if the samples do not cover the window.
///
/// drift (optional): dc_k/d delta, k = 0 .. max_bin, where delta [rad] is a
/// linear error of the angle reference over the window (the reference reads
/// delta too much at its end): the coefficients of x against the corrected
/// angle a0 + (angle - a0)(1 - delta / 2 pi R). With eps = delta / 2 pi R,
/// dc_k/d eps = y(a1) - c_k + (i k / R) G_k, G_k = (1/2 pi R) ∫ y phi e^{-i k phi/R} dphi
/// (differentiate under the integral, integrate by parts; y = x minus its mean).
std::vector<std::complex<double>> angle_fourier(std::span<const double> x, std::span<const double> angle,
                                                double angle_begin, double revolutions, int max_bin,
                                                std::vector<std::complex<double>>* drift = nullptr);

/// Mean of exponentially distributed values (|c_k|^2 of noise bins) that may
/// contain a few outliers (lines): truncated at the 99 % point of the
/// estimate and corrected for the truncation, iterated from the median.
double exponential_mean(std::vector<double> values, double* relative_se = nullptr);

/// Rician amplitude statistics: |s + n| with n complex Gaussian of total
/// variance s2 (E|n|^2 = s2) and |s| = nu.
double rice_mean(double nu, double s2);
double rice_variance(double nu, double s2);
/// d rice_mean / d nu: how the Rician mean follows its line amplitude nu (0 at nu = 0, where the
/// noise dominates; 1 for nu much larger than the noise).
double rice_mean_slope(double nu, double s2);
/// The line amplitude estimated from a measured amplitude A in noise of variance s2:
/// sqrt(max(A^2 - s2, 0)) (E[A^2] = nu^2 + s2).
inline double debiased_amplitude(double A, double s2) { return std::sqrt(std::max(A * A - s2, 0.0)); }

/// One feature: a DFT bin of the analysis window and the lines it carries.
struct FeatureCell {
  int bin = 0;               ///< bin k (order k / R)
  double order = 0;          ///< k / R
  std::vector<int> lines;    ///< indices into FeatureLayout::lines
  int segment = 0;           ///< noise segment (round(order / Zr))
};

struct LayoutOptions {
  double band_fraction = 0.3;   ///< analysed band: up to this fraction of the sample rate
  int carrier_sidebands = 0;    ///< j of the carrier family (0: 4 N)
  int max_mesh_harmonics = 80;  ///< cap on k
};

struct FeatureLayout {
  int revolutions = 1;          ///< R: window length in whole carrier revolutions (0: Q mesh cycles)
  int mesh_cycles = 0;          ///< Q: window length in whole mesh cycles when R = 0
  double window_revolutions = 1;  ///< W: window length in carrier revolutions (R, or Q / Zr)
  int max_bin = 0;              ///< highest bin analysed (bin k = carrier order k / W)
  double max_order = 0;         ///< max_bin / W
  int mesh_harmonics = 0;       ///< highest mesh harmonic in the band
  std::vector<OrderLine> lines;       ///< every labelled line (all families)
  std::vector<FeatureCell> cells;     ///< sorted by bin; the same for every channel
  std::vector<int> noise_bins;        ///< bins not near any line
  int segments = 1;
  /// Cells of family f (indexed by Component) and, per cell, its families.
  std::vector<std::vector<int>> family_cells;
  std::vector<std::vector<Component>> cell_families;
  /// Families with no whole period in a window of Q mesh cycles: their lines are not
  /// compared (empty for windows of whole carrier revolutions, which compare every family).
  std::vector<Component> unresolved;
};

/// Lines and cells for windows of R revolutions up to max_order.
FeatureLayout make_layout(const Kinematics& k, int planets, int revolutions, double max_order,
                          const LayoutOptions& options = {});

/// Lines and cells for windows of Q whole mesh cycles (W = Q / Zr carrier revolutions) up to
/// max_order: only the lines of the families that complete whole periods in Q mesh cycles
/// (Kinematics::completes_periods); the others are listed in `unresolved`.
FeatureLayout make_layout_mesh_cycles(const Kinematics& k, int planets, int mesh_cycles, double max_order,
                                      const LayoutOptions& options = {});

/// Fewest mesh cycles a recording must hold: two halves (fit and held-out) of one sun
/// period Zs each, the shortest window that resolves the mesh harmonics (period 1) and the
/// sun family (period Zs) together: 2 Zs.
int min_recording_mesh_cycles(int sun_teeth);

/// Half-window length Q [mesh cycles] for a recording of `mesh_cycles` mesh cycles that is
/// too short for two halves of whole carrier revolutions: the largest multiple of
/// lcm(Zs, Zp) that fits twice if one does (sun and planet families resolved), else of Zs.
/// 0 if not even 2 Zs fit.
int short_window_mesh_cycles(const Kinematics& k, double mesh_cycles);

/// A window of the recording: R whole carrier revolutions.
struct OrderWindow {
  std::string name;                  ///< "fit" or "held_out"
  double angle_begin_rad = 0;        ///< carrier angle at the window start (0 = first sample)
  std::size_t first_sample = 0, last_sample = 0;
  double t_begin_s = 0, t_end_s = 0;
};

/// Where the recording's carrier angle comes from (the model's is built the same way).
enum class AngleReference { SunSpeed, CarrierSpeed, Tacho, ConstantSpeed };

/// The recording in the order domain: windows, per-window amplitudes of every
/// bin and the per-cell noise variance.
struct RecordingSpectra {
  SpeedEstimate speed;
  std::string angle_source;
  AngleReference angle_reference = AngleReference::ConstantSpeed;
  Kinematics kinematics;             ///< at the estimated speed
  FeatureLayout layout;
  std::vector<int> channels;         ///< indices into Recording::channels (no tachos)
  std::vector<std::string> channel_names;
  std::vector<OrderWindow> windows;  ///< fit (first R revolutions), held_out (last R)
  /// amplitude[w][c][k] = |c_k| of channel c in window w, k = 0 .. max_bin.
  std::vector<std::vector<std::vector<double>>> amplitude;
  /// Noise: E|c_k|^2 of the noise in each cell, per channel [unit^2]: the
  /// per-sample noise variance (Hann periodogram of the whole recording
  /// between the sideband groups, exponential_mean) times the window's sum of
  /// squared weights; one value per channel for white noise, per segment of
  /// Zr orders for coloured noise.
  std::vector<std::vector<double>> noise_variance;
  std::vector<std::vector<double>> noise_relative_se;  ///< standard error of noise_variance / noise_variance
  std::vector<std::vector<int>> noise_group;  ///< cells sharing one noise estimate (for the null's draws)
  std::vector<bool> noise_local;     ///< per channel: coloured noise, local estimates used
  std::vector<double> noise_floor;   ///< per channel: mean over cells (for the report)
  std::vector<double> noise_sample_variance;  ///< per channel: white-noise variance per sample s_w^2
  /// D T of the angle reference's random walk [rad^2] (0 without a speed channel): the
  /// variance of its linear drift delta over a window, and strong lines leak the rest (the
  /// Brownian bridge) as A^2 o^2 D T / (4 pi^2 d^2) into the bins d away, added to noise_variance.
  double angle_diffusion_T = 0;
  /// The bridge's leak split by bin distance: bridge_leak[c][i][d - 1] is the part of
  /// noise_variance[c][i] leaked from the lines d = 1 .. kBridgeBins bins away (both sides)
  /// [unit^2]. Its realization is one number per window and distance, shared by every cell of
  /// every channel (the bridge's Fourier coefficient c_d), so the null draws it once per window
  /// (ModelComparison::null_draws) instead of as independent noise. Empty without a speed
  /// channel as the angle reference.
  static constexpr int kBridgeBins = 4;
  std::vector<std::vector<std::array<double, kBridgeBins>>> bridge_leak;
  /// amplitude_drift[w][c][k] = d|c_k|/d delta [unit/rad]: how window w's amplitudes move with
  /// a linear angle-reference error delta over the window (angle_fourier); empty without a
  /// speed channel as the angle reference.
  std::vector<std::vector<std::vector<double>>> amplitude_drift;
  std::vector<int> noise_bins_used;  ///< per channel
  /// A line the recording holds at no gear family's order (find_alien_lines): a rig's own tone
  /// (a line-counting encoder's images, mains, a fan) or another content the layout does not
  /// label. Its phase against the gear lines is the rig's, not the model's.
  struct AlienLine {
    double order = 0;      ///< carrier order
    double amplitude = 0;  ///< of the sinusoid [unit] (twice a window's |c_k| for a line on a bin)
    /// Another channel holds a line at this order too (mark_lines_in_other_channels): the
    /// machine's vibration, not this sensor's own tone; its leak is not in alien_leak.
    bool in_other_channels = false;
    /// The healthy baseline (or calibrated reference) recording holds a line at this order in the
    /// same channel (carry_baseline_alien_lines): the rig's own tone, whose leak V carries.
    bool in_baseline = false;
  };
  std::vector<std::vector<AlienLine>> alien_lines;  ///< per channel, by order
  /// Per channel and cell: the leak of the alien lines the healthy baseline also holds
  /// (in_baseline) into the cell's bin through the window's
  /// rectangular kernel, {sum of the leaks' squares, the largest square} [unit^2]
  /// (ModelComparison adds what their unknown phases leave, docs/diagnose.md §2).
  std::vector<std::vector<std::array<double, 2>>> alien_leak;
  /// [carrier orders] Two bins of the whole recording's spectrum: how near two lines at no gear
  /// order must lie to be one (mark_lines_in_other_channels, carry_baseline_alien_lines).
  double alien_tolerance = 0;
  /// Carrier orders the noise's bins keep clear of every mesh harmonic: 4 (N + 2), less where a
  /// stage's sideband groups leave too few bins between them (estimate_noise).
  double noise_clearance_orders = 0;
  std::vector<double> carrier_angle; ///< per sample (for synchronous averages)
};

/// Marks each line at no gear order that another channel also holds within `tolerance` carrier
/// orders (RecordingSpectra::AlienLine::in_other_channels). Why: a sensor's own tone (a
/// line-counting encoder's images, a pickup on one cable) is in its channel alone, while a line
/// of the machine (a speed oscillation, a quasi-periodic response, a subharmonic: content a
/// candidate may explain) reaches every sensor the structure carries it to. Only the former's
/// leak is carried in V (docs/diagnose.md section 2): on a stage whose teeth separate at the mesh
/// resonance the backlash's own lines at no gear order, in the sun speed and the mesh
/// accelerations alike, had hidden the backlash when every line was carried (session 63).
void mark_lines_in_other_channels(std::vector<std::vector<RecordingSpectra::AlienLine>>& lines, double tolerance);

/// The lines at no gear order of a healthy recording of the same rig at the same operating point,
/// by channel name, and how near [carrier orders] a line must lie to be the same one.
struct BaselineAlienLines {
  std::map<std::string, std::vector<double>> orders;
  double tolerance = 0;
};

/// Marks the recording's lines at no gear order that the baseline holds in the same channel within
/// the larger of the two recordings' tolerances (AlienLine::in_baseline) and sets alien_leak from
/// those alone. Why only those: a line the healthy recording of the rig also holds is the rig's
/// own tone (a line-counting encoder's images, a drive's harmonic), and its phase against the gear
/// lines differs between recordings; a line it does not hold may be the fault's own content (the
/// backlash of a stage whose teeth separate makes lines at no gear order in every channel). Without
/// a baseline none is carried. `tolerance`: the recording's own (two bins of its whole spectrum).
void carry_baseline_alien_lines(RecordingSpectra& s, const BaselineAlienLines& baseline, double tolerance);

struct OrderAnalysisOptions {
  LayoutOptions layout{};
  int max_window_revolutions = 3;    ///< R = min(floor(revolutions / 2), this)
  /// > 0: halves of this many whole mesh cycles whatever the recording's length (housing channels
  /// dropped, as for a short recording): a long reference analysed in a short recording's windows.
  int mesh_cycles = 0;
  /// > 0: the analysed band ends at this carrier order if the sample rate's edge
  /// (LayoutOptions::band_fraction fs over the measured carrier speed) lies above it: a recording
  /// and its healthy reference, whose measured speeds differ a little, analysed up to one edge.
  double max_order = 0;
};

/// Speed, angle, windows, amplitudes and noise of a recording: halves of R whole carrier
/// revolutions if it holds two, else of Q whole mesh cycles (short_window_mesh_cycles;
/// housing channels then dropped). Throws pw::InputError if it holds fewer than
/// min_recording_mesh_cycles mesh cycles.
RecordingSpectra analyse_recording(const Recording& recording, const model::StageSpec& stage,
                                   const OrderAnalysisOptions& options = {});

/// True when every channel and cell of `recording`'s analysis is in `reference`'s, in windows of
/// the same length: what a cell-by-cell comparison of a recording with a healthy reference
/// needs (the reference may have more). A line off the window's bins (sun, planet and
/// input-shaft families) leaks into the cells around it by a sinc of the window length, so equal
/// orders of unequal windows do not hold the same amplitudes.
bool reference_covers(const RecordingSpectra& reference, const RecordingSpectra& recording);

/// The analysis under which `recording` and its healthy `reference` share their cells
/// (docs/diagnose.md section 6b item 8), given the recording's default analysis: the default
/// first; else both in halves of the shorter one's whole carrier revolutions, or, when either is
/// shorter than two (halves of mesh cycles), both in halves of its mesh cycles (a 10 s healthy
/// recording is the reference of a 3 s one); else, when the two share their sample rate, as
/// well both up to the lower of their two band edges (each recording's edge is band_fraction fs
/// over its own measured carrier speed, so two recordings of one operating point can differ by
/// the cell at the edge). None when even that does not match (other channels, another sample
/// rate).
std::optional<OrderAnalysisOptions> common_analysis_options(const Recording& recording, const model::StageSpec& stage,
                                                            const RecordingSpectra& recording_default,
                                                            const Recording& reference,
                                                            const model::StageSpec& reference_stage);

/// What a simulation contributes to the comparison: for each recording
/// channel the amplitude of every bin 0 .. max_bin over the first W carrier
/// revolutions of its record (housing channels with gain 1; see
/// sensor_inputs for recomputing them).
struct ModelSpectra {
  std::vector<std::vector<double>> amplitude;  ///< [channel][bin]
  double mean_input_rpm = 0;                   ///< of the simulated record
  double time_step_s = 0;
  int steps_per_mesh = 0;
  int warmup_mesh_cycles = 0;
  /// Ring-mesh forces of every planet and the carrier angle over the compared
  /// samples (kept only when requested): housing channels for other sensor
  /// settings without a new simulation.
  std::vector<std::vector<double>> ring_force;
  std::vector<double> carrier_angle;
  std::vector<double> planet_angles_rad;
  /// alpha'_pr of the simulated stage (model/sensor.hpp Eq. S2); NaN where the simulation did not say
  double ring_pressure_angle_rad = std::numeric_limits<double>::quiet_NaN();
  /// The ring body's fixed-frame accelerations over the compared samples [m/s^2] and its mass [kg]
  /// (sensor.housing_path = ring_body, model/sensor.hpp Eq. S3), kept with the ring forces; empty
  /// and 0 for the other paths.
  std::vector<double> ring_acceleration_x, ring_acceleration_y;
  double ring_mass_kg = 0;
  std::vector<double> angle_theta;  ///< the angle reference at each kept sample [rad] (see model_spectra)
  /// Halves of Q mesh cycles only: per channel and bin, the mean square change of the amplitude
  /// over kLeakWindows - 1 other window starts ([unit^2]; empty otherwise; model_spectra).
  std::vector<std::vector<double>> leak_variance;
};

/// Window starts the model's spectrum is taken at in halves of Q mesh cycles (0, Q/4, Q/2,
/// 3Q/4 mesh cycles): three differences estimate the window-start variance of each bin, and
/// the model's record grows by 3Q/4 mesh cycles for them.
inline constexpr int kLeakWindows = 4;

/// Model channel that predicts a recording channel ("sun/speed", ...; "" for
/// housing accelerometers, computed from the ring forces, and tachos).
std::string model_channel_name(const SignalChannel& c);

/// The simulation channels model_spectra reads for this recording: the angle
/// references (carrier angle, both speeds), every planet's ring-mesh force
/// (housing sensors and the kept sensor inputs) and the channel that predicts
/// each recorded signal. The other ~35 channels are not stored.
model::OutputSelection model_channels(const Recording& recording, const RecordingSpectra& spectra,
                                      const model::SimulationConfig& config);

/// Features of a simulation result for the recording's channels and layout.
/// `sensor` is the configuration's sensor (angle replaced by each housing
/// channel's). Throws pw::SolverError if the record is shorter than W
/// carrier revolutions or lacks a channel.
ModelSpectra model_spectra(const model::SimulationResult& result, const Recording& recording,
                           const RecordingSpectra& spectra, const model::SimulationConfig& config,
                           bool keep_sensor_inputs);

/// Housing-channel amplitudes (bins 0 .. max_bin, gain 1) recomputed from the
/// kept sensor inputs for other sensor settings.
std::vector<double> housing_spectrum(const ModelSpectra& m, const model::SensorSettings& sensor, double angle_rad,
                                     double revolutions, int max_bin);

} // namespace pw::diagnose
