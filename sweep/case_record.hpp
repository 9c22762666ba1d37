// What a campaign keeps of one simulation case: the numbers the archive
// stores per case (docs/archive-format.md), small enough to send to rank 0
// and to journal, and its byte serialization.
//
//   model::SimulationResult r = model::simulate(config);
//   CaseRecord rec = make_case_record(r, {.time_history_decimation = 4});
//   rec.index = 17;
//   std::vector<char> bytes = serialize(rec);     // MPI message, journal file
//   CaseRecord back = deserialize(bytes);         // == rec
//
// Record contents (units SI):
//   scalars  every scalar of the result (mesh_frequency, efficiency,
//            load_sharing_factor/<i>, max_wear/<family>, natural_frequency/<k>,
//            ...) plus, for the sun-planet and planet-ring meshes of planet 0
//            (<mesh> = sun_planet/0, planet_ring/0):
//              <mesh>/acceleration_rms                sqrt(mean a^2)     [m/s^2]
//              <mesh>/acceleration_peak               max |a|            [m/s^2]
//              <mesh>/acceleration_dominant_frequency bin of the largest spectral amplitude above 0 Hz [Hz]
//              <mesh>/force_mean, <mesh>/force_peak   [N]
//              <mesh>/deflection_mean                 [m]
//            transmission_error/peak_to_peak [m]; and in wear runs
//            backlash_growth/sun_planet, backlash_growth/planet_ring [m]
//            (last minus first wear update).
//   wear     per flank family: the final wear depth of each element averaged
//            over the teeth and its maximum over the teeth, and the elements'
//            distance from the pitch point.
//   spectra  amplitude spectra (Hann window, peak-amplitude scaling) of the
//            mesh-line acceleration of planet 0's two meshes, optionally cut
//            at a maximum frequency (the statistics above use every bin).
//   time history (optional) every k-th recorded sample of planet 0's mesh
//            deflections, forces and accelerations and of the transmission
//            error, with its time axis.
#pragma once

#include "core/error.hpp"
#include "model/result.hpp"

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pw::sweep {

enum class CaseStatus { Pending, Done, Failed };
std::string_view to_string(CaseStatus s);
/// "pending", "done", "failed"; throws std::invalid_argument otherwise.
CaseStatus case_status_from(std::string_view s);

struct NamedScalar {
  std::string name, unit, description;
  double value = 0;
};

/// The final wear of one flank family (sun, planet_<i>/sun_side, ...).
struct FinalWear {
  std::string family;
  std::vector<double> distance_from_pitch_point_m;  ///< per element [m]
  std::vector<double> mean_depth_m;                 ///< per element, averaged over teeth [m]
  std::vector<double> max_depth_m;                  ///< per element, maximum over teeth [m]
};

struct SpectrumRecord {
  std::string channel;  ///< e.g. "sun_planet/0/acceleration"
  std::string unit;     ///< of the amplitude
  std::vector<double> frequency_Hz, amplitude;
};

struct TimeHistoryRecord {
  std::vector<double> time_s;
  std::vector<model::Channel> channels;  ///< each as long as time_s
};

struct CaseRecord {
  std::int64_t index = -1;  ///< case index in the design
  CaseStatus status = CaseStatus::Pending;
  std::string message;      ///< failed: the reason; done: a note (wear stopped early), usually ""
  double wall_time_s = 0;   ///< time to simulate and summarize [s]
  int rank = -1;            ///< MPI rank that computed it
  std::vector<NamedScalar> scalars;
  std::vector<FinalWear> wear;
  std::vector<SpectrumRecord> spectra;
  TimeHistoryRecord time_history;

  const NamedScalar* find_scalar(std::string_view name) const;
};

struct RecordOptions {
  int time_history_decimation = 0;       ///< 0: no time histories
  double spectrum_max_frequency_Hz = 0;  ///< keep spectrum bins up to this frequency [Hz]; 0: all
};

/// Summarizes a finished simulation (status Done; index, wall time and rank
/// are left for the caller). A wear run that stopped early keeps its reason
/// in `message`. Throws std::invalid_argument if the result lacks the
/// channels of planet 0's meshes.
CaseRecord make_case_record(const model::SimulationResult& result, const RecordOptions& options);

/// A failed case: status Failed with its reason.
CaseRecord failed_record(std::int64_t index, std::string message);

/// Malformed bytes (truncated, wrong magic or version). The journal reader
/// skips such a record (the case runs again); anywhere else it is exit code 5.
class RecordFormatError : public Error {
public:
  using Error::Error;
};

/// Byte image of a record (host byte order; rank 0 and the journal are on
/// machines of one architecture). Begins with a magic and a format version.
std::vector<char> serialize(const CaseRecord& record);
CaseRecord deserialize(std::span<const char> bytes);

/// Minimal append-only byte writer / bounds-checked reader used for records
/// and the driver's messages.
class ByteWriter {
public:
  void u32(std::uint32_t v) { raw(&v, sizeof v); }
  void i64(std::int64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void str(std::string_view s);
  void f64s(std::span<const double> v);
  std::vector<char> take() { return std::move(bytes_); }

private:
  void raw(const void* p, std::size_t n);
  std::vector<char> bytes_;
};

class ByteReader {
public:
  explicit ByteReader(std::span<const char> bytes) : bytes_(bytes) {}
  std::uint32_t u32();
  std::int64_t i64();
  double f64();
  std::string str();
  std::vector<double> f64s();
  bool at_end() const noexcept { return pos_ == bytes_.size(); }

private:
  void raw(void* p, std::size_t n);
  std::span<const char> bytes_;
  std::size_t pos_ = 0;
};

} // namespace pw::sweep
