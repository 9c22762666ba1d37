// HDF5 layout of one simulation (documented in docs/output-format.md):
//
//   /                        attrs: format, format_version, software_version,
//                                   build_flags, created_utc, units_convention
//   /config/toml             resolved configuration (to_toml), UTF-8 string
//   /time_history/time       [s]             attrs: unit, description
//   /time_history/<channel>  e.g. sun_planet/0/deflection; attrs: unit, description
//   /scalars/<name>          0-d double;     attrs: unit, description
//   /curves/<name>/x, /y     attrs on the group: x_name, x_unit, y_name, y_unit,
//                            description; on x and y: unit, description
//   /spectra/<name>/frequency [Hz], /amplitude [signal unit];
//                            attrs on the group: unit, window, scaling
//   /wear                    only if result.wear has updates; attrs: stop_reason, description
//   /wear/mesh_cycles        [1]  (updates)
//   /wear/backlash           [m]  (updates, 2); attr columns = "sun_planet,planet_ring"
//   /wear/<flank>/depth      [m]  (updates, teeth, elements), compressed; flank e.g.
//                            sun, planet_0/sun_side; attrs on the group: teeth, elements
//   /wear/<flank>/distance_from_pitch_point [m] (elements), /max_depth [m] (updates)
//   /wear/snapshots/<k>/     attr mesh_cycles; time_history/time [s], time_history/<channel>,
//                            spectra/<name>/frequency [Hz], /amplitude (as /spectra)
//
// In Python: h5py.File(p)["time_history/sun_planet/0/deflection"][:]
#pragma once

#include "io/hdf5_file.hpp"

#include "config/stage.hpp"
#include "model/result.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pw::io {

/// One amplitude spectrum to store under /spectra/<name>.
struct SpectrumRecord {
  std::string name;     ///< '/'-separated, e.g. "sun_planet/0/deflection"
  std::string unit;     ///< unit of the amplitude (= of the analysed signal)
  std::string window;   ///< e.g. "hann" (signal::to_string(Window))
  std::string scaling;  ///< e.g. signal::kPeakAmplitudeScaling
  std::vector<double> frequency_Hz, amplitude;
};

/// Value of the root attribute "format" and "format_version"; the version
/// grows when the layout changes incompatibly.
inline constexpr std::string_view kOutputFormat = "planetwear.simulation";
inline constexpr std::int64_t kOutputFormatVersion = 1;

/// How the large datasets (time histories, curves, spectra, wear depths with
/// 4096 or more values) are stored: level 0 contiguous and uncompressed (the
/// default: deflate costs ~4x the physics of a 1 s run and halves the file,
/// docs/benchmark.md session 20), 1..9 chunked with shuffle + deflate at that
/// level.
struct WriteOptions {
  int compression_level = 0;  ///< 0 (none) .. 9 (smallest, slowest)
};

/// Writes the whole layout above into an empty (newly created) file. Time
/// histories and wear depths with 4096 or more values are stored as
/// `options` says. Throws std::invalid_argument, before writing anything,
/// for an inconsistent result (a channel not as long as its time base, x/y or
/// frequency/amplitude of different lengths, names that are empty, absolute,
/// contain "." or ".." components, a channel named "time"; wear: backlash not
/// updates x 2, a flank with < 1 tooth or element, positions not one per
/// element, depths not updates x teeth x elements, a flank name used twice or
/// starting with mesh_cycles/backlash/snapshots, flanks or snapshots without
/// updates, a snapshot spectrum with frequencies and amplitudes of different
/// lengths) and pw::io::IoError for HDF5 failures (including two objects of
/// the same name).
void write_simulation(H5File& file, const model::SimulationConfig& config, const model::SimulationResult& result,
                      const std::vector<SpectrumRecord>& spectra, const WriteOptions& options = {});

/// PLANETWEAR_VERSION and PLANETWEAR_BUILD_FLAGS as compiled into pw::io.
std::string_view software_version();
std::string_view build_flags();

} // namespace pw::io
