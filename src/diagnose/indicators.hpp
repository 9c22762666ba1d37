// Gear condition indicators of a planetary stage's signals: time-synchronous
// averages (TSA) per gear, planet-separated for a housing accelerometer, and
// the indicators of signal/condition_indicators.hpp on each
// (docs/indicators.md).
//
// Every TSA is taken on the mesh-cycle coordinate u = Zr theta_c / (2 pi)
// (theta_c the carrier angle; the ring is fixed, so the mesh advances Zr
// periods per carrier revolution), resampled to S samples per mesh cycle:
//  * sun:     sun revolutions relative to the carrier, Zs mesh cycles each
//             (a sun tooth meets the same planet again after Zs mesh cycles);
//             mesh order Zs;
//  * planet:  planet revolutions relative to the carrier, Zp mesh cycles;
//             mesh order Zp;
//  * carrier: carrier revolutions, Zr mesh cycles (a ring tooth meets the
//             same planet again); mesh order Zr.
// Which gears per channel:
//  * housing accelerometer: sun and carrier (plain TSA) and every planet i
//    (planet-separated TSA: each sample weighted by a Hann window in the
//    carrier angle centred where planet i passes the sensor,
//    signal::weighted_synchronous_average; McFadden & Smith 1985, McFadden
//    1994);
//  * sun-planet mesh acceleration of planet p: sun and planet p;
//  * planet-ring mesh acceleration of planet p: planet p and carrier;
//  * speeds and tacho: none (they give the angle reference).
#pragma once

#include "config/stage.hpp"
#include "diagnose/recording.hpp"
#include "signal/condition_indicators.hpp"

#include <map>
#include <span>
#include <string>
#include <vector>

namespace pw::diagnose {

struct IndicatorOptions {
  /// Angle-domain samples per mesh cycle S; 0 = max(kMinSamplesPerMesh,
  /// ceil(sample rate / mesh frequency)): the resampled grid keeps the
  /// recording's bandwidth. Allowed: 0 or [kMinSamplesPerMesh, kMaxSamplesPerMesh].
  int samples_per_mesh = 0;
  /// Shaft orders 1 .. H removed from the regular/difference/residual
  /// signals (signal::GearOrders); allowed [0, 8].
  int shaft_harmonics = 2;
  /// Half-width h of the planet-separation window in carrier angle [rad];
  /// 0 = pi / N (each planet's window spans the sector nearer to it than to
  /// its neighbours). Allowed: 0 or (0, pi].
  double planet_window_half_width_rad = 0;
  /// A planet-separated average needs every tooth position covered with at
  /// least this weight sum (1 = one passage straight past the sensor).
  double min_planet_window_weight = 0.25;
};

/// Fewest samples per mesh cycle: 16 resolve the first 8 mesh harmonics (Nyquist at S/2 per mesh cycle).
inline constexpr int kMinSamplesPerMesh = 16;
/// Most samples per mesh cycle: a simulation at 100 rpm stores ~12800 per mesh cycle (every time step);
/// resampling a denser signal to fewer points interpolates without an anti-alias filter.
inline constexpr int kMaxSamplesPerMesh = 16384;
/// Most shaft orders removed (--shaft-harmonics): the low orders of eccentricity and misalignment;
/// for a gear with fewer than H + 2 teeth H is clamped to Z - 2 (the shaft orders stay below Z - 1).
inline constexpr int kMaxShaftHarmonics = 8;

/// One TSA of one channel.
struct GearAverage {
  std::string gear;         ///< "sun", "planet", "carrier"
  int planet = -1;          ///< planet index for "planet" (else -1)
  int teeth = 0;            ///< mesh order Z of the TSA (Zs, Zp, Zr)
  int revolutions = 0;      ///< revolutions averaged (R)
  int samples_per_mesh = 0; ///< S; the TSA has Z S samples
  std::string method;       ///< "TSA" or "planet-separated TSA (Hann window, half-width ... rad)"
  std::vector<double> tsa;  ///< one revolution, in the channel's unit
};

/// A TSA that could not be formed, and why.
struct SkippedAverage {
  std::string gear;
  int planet = -1;
  std::string reason;
};

/// One channel's signal and what it measures.
struct ChannelSignal {
  std::string name;
  Quantity quantity = Quantity::HousingAcceleration;
  std::string unit;
  int planet = 0;               ///< mesh accelerations: whose mesh
  double sensor_angle_rad = 0;  ///< housing accelerometer angle (docs/recordings.md "Angles")
  std::span<const double> values;
};

/// The TSAs of one channel (file comment). `time_s` uniform and increasing,
/// `carrier_angle_rad` the absolute carrier angle at each sample (housing
/// frame: planet i is at psi_i + theta_c), strictly increasing. Gears whose
/// average cannot be formed (recording shorter than one revolution, planet
/// positions not covered) are appended to `skipped` with the reason.
/// Throws pw::InputError for options out of range (naming the option).
std::vector<GearAverage> gear_averages(std::span<const double> time_s, std::span<const double> carrier_angle_rad,
                                       const ChannelSignal& channel, const model::SimulationConfig& config,
                                       const IndicatorOptions& options, std::vector<SkippedAverage>* skipped);

/// Indicators of one TSA of one channel.
struct IndicatorRow {
  std::string channel, quantity, unit;
  GearAverage average;  ///< its tsa is dropped (empty) unless keep_tsa
  signal::ConditionIndicators values;
};

/// Residual and envelope variances of the earlier records of a run, per
/// (channel, gear, planet), for NA4 and NB4 (signal::na4).
using RunHistory = std::map<std::string, std::pair<std::vector<double>, std::vector<double>>>;

/// Indicators of every TSA of `channel`; with `history`, NA4/NB4 are
/// normalized by the run so far and the history is extended.
std::vector<IndicatorRow> channel_indicators(std::span<const double> time_s, std::span<const double> carrier_angle_rad,
                                             const ChannelSignal& channel, const model::SimulationConfig& config,
                                             const IndicatorOptions& options, std::vector<SkippedAverage>* skipped,
                                             RunHistory* history = nullptr, bool keep_tsa = false);

/// Every channel of a recording (speeds and tacho give the angle reference:
/// order_analysis.hpp estimate_speed / carrier_angle; the carrier angle at the
/// first sample is the estimated carrier speed times its time, docs/recordings.md
/// "Angles"). `angle_source` (optional) says how the angle was obtained.
std::vector<IndicatorRow> recording_indicators(const Recording& recording, const model::SimulationConfig& config,
                                               const IndicatorOptions& options, std::vector<SkippedAverage>* skipped,
                                               std::string* angle_source = nullptr, bool keep_tsa = false);

/// Field names of signal::ConditionIndicators in output order, with their
/// units ("signal" = the channel's unit, "1" = dimensionless).
struct IndicatorField {
  const char* name;
  const char* unit;
  double signal::ConditionIndicators::*member;
};
std::span<const IndicatorField> indicator_fields();

} // namespace pw::diagnose
