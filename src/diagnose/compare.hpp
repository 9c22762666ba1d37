// Model against recording: simulate the stage at the recording's operating
// point over the same absolute time span and compare both through the same
// linear features, so that only measurement noise separates them when the
// model is right (docs/diagnose.md §3).
//
// Features of one analysis window [t_a, t_a + T) of n recording samples, per
// channel c: Hann-windowed DFT bins k = k_min .. k_max (f_k = k / T, up to
// (kAnalysedMeshHarmonics + 1/2) f_m) of the mean-removed signal. The model's
// bins are the same Riemann sum of its own full-rate signal on a grid q times
// finer (cubic interpolation, no aliasing of the stiff modes the recording's
// anti-alias filter removed). With white noise of variance s_c^2 (estimated
// from the recording, features.hpp) the real and imaginary parts of
// Delta X_k are N(0, 3 n s_c^2 / 16), and neighbouring bins are correlated
// (rho_1 = -2/3, rho_2 = 1/6). The residual vector is
//   r = (Re, Im)(X_rec - g X_model) / sqrt(3 n s_c^2 / 16)
// and chi2 = |r|^2 has mean m (= len r) and variance 2 m tr(R^2)/m = 3.89 m:
// it is treated as c chi2(m / c) with c = 1.944 (Satterthwaite), which gives
// the noise bound and the information criteria (diagnose.hpp).
//
// g = 1 except for housing accelerometers when the sensor gain is profiled
// (closed-form least squares: a nuisance that never needs a simulation).
// Simulations are cached (key: resolved configuration, end time, time step)
// and thread-safe: evaluate() may run on several OpenMP threads at once.
#pragma once

#include "diagnose/kinematics.hpp"
#include "diagnose/features.hpp"
#include "diagnose/recording.hpp"
#include "model/stage.hpp"

#include <complex>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace pw::diagnose {

/// Correlation of the Hann bins' noise: chi2 ~ c chi2(m / c), c = 1 + 2 (2/3)^2 + 2 (1/6)^2.
inline constexpr double kHannChi2Scale = 1.0 + 2.0 * 4.0 / 9.0 + 2.0 / 36.0;

/// A span of the recording analysed as one window.
struct AnalysisWindow {
  std::string name;          ///< "fit" or "held_out"
  std::size_t begin = 0;     ///< first recording sample
  std::size_t count = 0;     ///< samples
  double t_begin_s = 0, t_end_s = 0;  ///< absolute times of the first and one past the last sample
  int k_min = 3, k_max = 0;  ///< DFT bins compared
};

/// The model's signals needed for the comparison, from one simulation.
struct SimulatedSignals {
  double t0_s = 0, dt_s = 0;            ///< absolute time of sample 0, time step
  std::vector<std::vector<double>> channels;  ///< per recording channel (empty for housing channels)
  std::vector<std::vector<double>> ring_force_N;  ///< per planet: planet-ring mesh force (for housing channels)
  std::vector<double> carrier_angle_rad;
  std::vector<double> planet_angles_rad;
  int warmup_mesh_cycles = 0;
  int steps_per_mesh = 0;
  double t_end_s() const;
};

/// Result of comparing one model configuration with one window.
struct WindowComparison {
  std::vector<double> residual;             ///< whitened (diagonal) residual, see above
  double chi2 = 0;                          ///< |residual|^2
  std::vector<double> chi2_per_channel;     ///< same, per recording channel
  std::vector<int> dof_per_channel;         ///< real residuals per channel
  double sensor_gain = 0;                   ///< gain used for housing channels [m/s^2 per N] (profiled or configured)
  double sensor_gain_std = 0;               ///< its standard error when profiled
};

/// Options of the comparison.
struct CompareOptions {
  int window_carrier_revolutions = 1;  ///< length of each analysis window
  double max_mesh_harmonic = 3.5;      ///< bins up to this multiple of f_m
  int k_min = 3;                       ///< lowest bin (bins 0-2 carry the offset through the Hann window)
};

class ModelComparison {
public:
  /// Prepares the recording: usable channels, noise per channel, the fit
  /// window (first carrier revolution after `earliest_start_s`) and the
  /// held-out window (the last carrier revolution), their DFT bins. Throws
  /// pw::InputError if the recording is shorter than two windows.
  ModelComparison(const Recording& recording, const model::SimulationConfig& base, double earliest_start_s,
                  CompareOptions options = {});

  const Recording& recording() const { return rec_; }
  const Kinematics& kinematics() const { return kin_; }
  const AnalysisWindow& window(int w) const { return windows_.at(static_cast<std::size_t>(w)); }
  int windows() const { return static_cast<int>(windows_.size()); }
  const std::vector<NoiseEstimate>& noise() const { return noise_; }
  const std::vector<int>& channels() const { return used_; }  ///< indices into recording().channels
  /// Real residuals of window w.
  int dof(int w) const;

  /// Simulates `config` from t = 0 so that its record covers [t_begin, t_end]
  /// (warm-up capped to end before t_begin). fixed_dt > 0 forces the time
  /// step (Jacobian columns share one). Cached.
  std::shared_ptr<const SimulatedSignals> simulate(const model::SimulationConfig& config, double t_end,
                                                   double fixed_dt = 0) const;

  /// Compares a simulation with window w. profile_gain: fit the housing
  /// sensor gain in closed form (else use config.sensor.gain_m_s2_per_N).
  WindowComparison compare(const SimulatedSignals& sim, const model::SimulationConfig& config, int w,
                           bool profile_gain) const;

  /// Model signal of recording channel `ch` on the recording's samples of
  /// [begin, begin + count), band-limited to (0, max_Hz] (FFT brick wall on
  /// the fine grid) so that it compares with the recording sample by sample.
  std::vector<double> model_on_recording(const SimulatedSignals& sim, const model::SimulationConfig& config,
                                         double sensor_gain, int ch, std::size_t begin, std::size_t count,
                                         double max_Hz) const;
  /// Recording channel `ch` on [begin, begin + count), mean removed and
  /// band-limited the same way.
  std::vector<double> recording_band_limited(int ch, std::size_t begin, std::size_t count, double max_Hz) const;

  /// Simulations run so far (cache misses) and their wall time [s].
  long simulations() const;
  double simulation_seconds() const;

private:
  std::vector<double> fine_signal(const SimulatedSignals& sim, const model::SimulationConfig& config, int ch,
                                  double t_begin, std::size_t n_fine, double dt_fine) const;
  std::vector<std::complex<double>> hann_bins(std::span<const double> x, int k_min, int k_max) const;

  const Recording& rec_;
  model::SimulationConfig base_;
  CompareOptions opt_;
  Kinematics kin_;
  std::vector<int> used_;
  std::vector<NoiseEstimate> noise_;
  std::vector<AnalysisWindow> windows_;
  std::vector<std::vector<std::vector<std::complex<double>>>> rec_bins_;  // [window][channel][bin]

  mutable std::mutex mutex_;
  mutable std::map<std::string, std::shared_ptr<const SimulatedSignals>> cache_;
  mutable std::vector<std::string> cache_order_;
  mutable std::map<int, int> warmup_seen_;  // has-tooth-level-features -> last warm-up cycles
  mutable long sims_ = 0;
  mutable double sim_seconds_ = 0;
};

/// Name of the simulation channel that models a recording channel, or "" for
/// housing accelerometers (computed from the ring forces, model/sensor.hpp)
/// and tachos (not compared).
std::string model_channel_name(const SignalChannel& c);

} // namespace pw::diagnose
