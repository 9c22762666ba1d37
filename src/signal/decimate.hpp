// Decimation by an integer factor through a zero-phase anti-alias FIR: the one
// copy used by `planetwear synth` and the tests that make recordings.
//
// The filter is a Blackman-windowed sinc (Oppenheim & Schafer, Discrete-Time
// Signal Processing, 3rd ed., Table 7.2: peak approximation error about -74 dB,
// transition width about 9.2 pi / M for a filter of order M = 2 half), cutoff 0.4
// of the new sample rate so that the band up to its Nyquist frequency 0.5 is in
// the transition, with unit DC gain (speeds and offsets pass unchanged).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace pw::signal {

/// The taps h_m, m = -half ... half, of the anti-alias filter for decimation by `factor`.
struct DecimationFilter {
  int factor = 1;            ///< k: one output sample per k input samples [-]
  int half = 0;              ///< taps on each side of the centre: half_taps_per_factor * k (0 for k = 1)
  std::vector<double> taps;  ///< 2 half + 1 values, summing to 1
};

/// The filter for decimation by k >= 1 with half_taps_per_factor k taps on each
/// side (16: 32k + 1 taps, ~60 dB stop band; 32: 64k + 1 taps, sharper). k = 1 is
/// the identity (one tap of 1). Throws pw::InputError for k < 1 or
/// half_taps_per_factor < 1.
DecimationFilter decimation_filter(int k, int half_taps_per_factor);

/// Output j = sum_m h_m x[first + j k + m], j = 0 ... count - 1: the filtered
/// signal at input samples first, first + k, ... (zero phase: output j belongs to
/// input sample first + j k). The whole kernel must lie inside x: first >= half
/// and first + (count - 1) k + half < x.size(), else pw::InputError.
std::vector<double> decimate(std::span<const double> x, const DecimationFilter& filter, std::size_t first,
                             std::size_t count);

} // namespace pw::signal
