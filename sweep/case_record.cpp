#include "case_record.hpp"

#include "signal/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace pw::sweep {
namespace {

constexpr std::uint32_t kRecordMagic = 0x52435750;  // "PWCR" little-endian
constexpr std::uint32_t kRecordVersion = 1;

const model::Channel& channel(const model::SimulationResult& r, const std::string& name) {
  const model::Channel* c = r.find(name);
  if (!c) throw std::invalid_argument("simulation result has no channel '" + name + "'");
  return *c;
}

} // namespace

std::string_view to_string(CaseStatus s) {
  switch (s) {
  case CaseStatus::Pending: return "pending";
  case CaseStatus::Done: return "done";
  case CaseStatus::Failed: return "failed";
  }
  return "?";
}

CaseStatus case_status_from(std::string_view s) {
  if (s == "pending") return CaseStatus::Pending;
  if (s == "done") return CaseStatus::Done;
  if (s == "failed") return CaseStatus::Failed;
  throw std::invalid_argument("unknown case status '" + std::string(s) + "'");
}

const NamedScalar* CaseRecord::find_scalar(std::string_view name) const {
  for (const auto& s : scalars)
    if (s.name == name) return &s;
  return nullptr;
}

CaseRecord make_case_record(const model::SimulationResult& r, const RecordOptions& options) {
  CaseRecord rec;
  rec.status = CaseStatus::Done;
  rec.message = r.wear.stop_reason;
  for (const auto& s : r.scalars) rec.scalars.push_back({s.name, s.unit, s.description, s.value});
  auto add = [&](std::string name, std::string unit, std::string description, double value) {
    rec.scalars.push_back({std::move(name), std::move(unit), std::move(description), value});
  };

  // Planet 0's two meshes: acceleration statistics, spectrum, forces.
  for (const std::string mesh : {"sun_planet/0", "planet_ring/0"}) {
    const model::Channel& a = channel(r, mesh + "/acceleration");
    const model::Channel& f = channel(r, mesh + "/force");
    const model::Channel& d = channel(r, mesh + "/deflection");
    const double n = static_cast<double>(std::max<std::size_t>(a.values.size(), 1));
    double sq = 0, peak = 0;
    for (const double x : a.values) {
      sq += x * x;
      peak = std::max(peak, std::fabs(x));
    }
    const signal::Spectrum s = signal::amplitude_spectrum(a.values, r.time_step_s, signal::Window::Hann);
    double dominant = std::numeric_limits<double>::quiet_NaN(), best = -1;
    for (std::size_t k = 1; k < s.amplitude.size(); ++k)
      if (s.amplitude[k] > best) {
        best = s.amplitude[k];
        dominant = s.frequency_Hz[k];
      }
    double fsum = 0, fpeak = 0, dsum = 0;
    for (const double x : f.values) {
      fsum += x;
      fpeak = std::max(fpeak, std::fabs(x));
    }
    for (const double x : d.values) dsum += x;
    const std::string which = mesh.starts_with("sun") ? "sun-planet" : "planet-ring";
    add(mesh + "/acceleration_rms", a.unit, "RMS of the " + which + " mesh-line acceleration of planet 0, sqrt(mean a^2)",
        std::sqrt(sq / n));
    add(mesh + "/acceleration_peak", a.unit, "largest |a| of the " + which + " mesh-line acceleration of planet 0", peak);
    add(mesh + "/acceleration_dominant_frequency", "Hz",
        "frequency of the largest amplitude (above 0 Hz) of the " + which + " acceleration spectrum of planet 0",
        dominant);
    add(mesh + "/force_mean", f.unit, "mean dynamic normal force of the " + which + " mesh of planet 0",
        fsum / static_cast<double>(std::max<std::size_t>(f.values.size(), 1)));
    add(mesh + "/force_peak", f.unit, "largest |F| of the " + which + " mesh of planet 0", fpeak);
    add(mesh + "/deflection_mean", d.unit, "mean deflection of the " + which + " mesh of planet 0",
        dsum / static_cast<double>(std::max<std::size_t>(d.values.size(), 1)));
    std::size_t bins = s.frequency_Hz.size();
    if (options.spectrum_max_frequency_Hz > 0)
      while (bins > 1 && s.frequency_Hz[bins - 1] > options.spectrum_max_frequency_Hz) --bins;
    rec.spectra.push_back({a.name, a.unit, {s.frequency_Hz.begin(), s.frequency_Hz.begin() + static_cast<std::ptrdiff_t>(bins)},
                           {s.amplitude.begin(), s.amplitude.begin() + static_cast<std::ptrdiff_t>(bins)}});
  }
  if (const model::Channel* te = r.find("transmission_error"); te && !te->values.empty()) {
    const auto [lo, hi] = std::minmax_element(te->values.begin(), te->values.end());
    add("transmission_error/peak_to_peak", te->unit, "peak-to-peak transmission error at the sun's base circle",
        *hi - *lo);
  }

  // Wear: final profiles and backlash growth.
  const model::WearHistory& w = r.wear;
  const std::size_t updates = w.mesh_cycles.size();
  if (updates > 0) {
    for (const auto& fh : w.flanks) {
      const auto teeth = static_cast<std::size_t>(fh.teeth), elements = static_cast<std::size_t>(fh.elements);
      if (teeth == 0 || elements == 0 || fh.depth_m.size() != updates * teeth * elements)
        throw std::invalid_argument("wear history of '" + fh.name + "' is not updates x teeth x elements");
      FinalWear fw{fh.name, fh.distance_from_pitch_point_m, std::vector<double>(elements, 0.0),
                   std::vector<double>(elements, -std::numeric_limits<double>::infinity())};
      const double* last = fh.depth_m.data() + (updates - 1) * teeth * elements;
      for (std::size_t t = 0; t < teeth; ++t)
        for (std::size_t e = 0; e < elements; ++e) {
          fw.mean_depth_m[e] += last[t * elements + e] / static_cast<double>(teeth);
          fw.max_depth_m[e] = std::max(fw.max_depth_m[e], last[t * elements + e]);
        }
      rec.wear.push_back(std::move(fw));
    }
    if (w.backlash_m.size() == 2 * updates) {
      add("backlash_growth/sun_planet", "m", "growth of the sun-planet backlash over the wear run",
          w.backlash_m[2 * (updates - 1)] - w.backlash_m[0]);
      add("backlash_growth/planet_ring", "m", "growth of the planet-ring backlash over the wear run",
          w.backlash_m[2 * (updates - 1) + 1] - w.backlash_m[1]);
    }
  }

  // Decimated time histories.
  if (const int k = options.time_history_decimation; k > 0) {
    const auto step = static_cast<std::size_t>(k);
    for (std::size_t i = 0; i < r.time_s.size(); i += step) rec.time_history.time_s.push_back(r.time_s[i]);
    for (const std::string name : {"sun_planet/0/deflection", "sun_planet/0/force", "sun_planet/0/acceleration",
                                   "planet_ring/0/deflection", "planet_ring/0/force", "planet_ring/0/acceleration",
                                   "transmission_error"}) {
      const model::Channel* c = r.find(name);
      if (!c || c->values.size() != r.time_s.size()) continue;
      model::Channel d{c->name, c->unit, c->description, {}};
      for (std::size_t i = 0; i < c->values.size(); i += step) d.values.push_back(c->values[i]);
      rec.time_history.channels.push_back(std::move(d));
    }
  }
  return rec;
}

CaseRecord failed_record(std::int64_t index, std::string message) {
  CaseRecord r;
  r.index = index;
  r.status = CaseStatus::Failed;
  r.message = std::move(message);
  return r;
}

// --- bytes -------------------------------------------------------------------

void ByteWriter::raw(const void* p, std::size_t n) {
  const auto* c = static_cast<const char*>(p);
  bytes_.insert(bytes_.end(), c, c + n);
}

void ByteWriter::str(std::string_view s) {
  i64(static_cast<std::int64_t>(s.size()));
  raw(s.data(), s.size());
}

void ByteWriter::f64s(std::span<const double> v) {
  i64(static_cast<std::int64_t>(v.size()));
  raw(v.data(), v.size() * sizeof(double));
}

void ByteReader::raw(void* p, std::size_t n) {
  if (n > bytes_.size() - pos_) throw RecordFormatError("record truncated");
  std::memcpy(p, bytes_.data() + pos_, n);
  pos_ += n;
}

std::uint32_t ByteReader::u32() {
  std::uint32_t v;
  raw(&v, sizeof v);
  return v;
}

std::int64_t ByteReader::i64() {
  std::int64_t v;
  raw(&v, sizeof v);
  return v;
}

double ByteReader::f64() {
  double v;
  raw(&v, sizeof v);
  return v;
}

std::string ByteReader::str() {
  const std::int64_t n = i64();
  if (n < 0 || static_cast<std::uint64_t>(n) > bytes_.size() - pos_) throw RecordFormatError("record truncated");
  std::string s(static_cast<std::size_t>(n), '\0');
  raw(s.data(), s.size());
  return s;
}

std::vector<double> ByteReader::f64s() {
  const std::int64_t n = i64();
  if (n < 0 || static_cast<std::uint64_t>(n) > (bytes_.size() - pos_) / sizeof(double))
    throw RecordFormatError("record truncated");
  std::vector<double> v(static_cast<std::size_t>(n));
  raw(v.data(), v.size() * sizeof(double));
  return v;
}

std::vector<char> serialize(const CaseRecord& r) {
  ByteWriter w;
  w.u32(kRecordMagic);
  w.u32(kRecordVersion);
  w.i64(r.index);
  w.u32(static_cast<std::uint32_t>(r.status));
  w.str(r.message);
  w.f64(r.wall_time_s);
  w.i64(r.rank);
  w.i64(static_cast<std::int64_t>(r.scalars.size()));
  for (const auto& s : r.scalars) {
    w.str(s.name);
    w.str(s.unit);
    w.str(s.description);
    w.f64(s.value);
  }
  w.i64(static_cast<std::int64_t>(r.wear.size()));
  for (const auto& f : r.wear) {
    w.str(f.family);
    w.f64s(f.distance_from_pitch_point_m);
    w.f64s(f.mean_depth_m);
    w.f64s(f.max_depth_m);
  }
  w.i64(static_cast<std::int64_t>(r.spectra.size()));
  for (const auto& s : r.spectra) {
    w.str(s.channel);
    w.str(s.unit);
    w.f64s(s.frequency_Hz);
    w.f64s(s.amplitude);
  }
  w.f64s(r.time_history.time_s);
  w.i64(static_cast<std::int64_t>(r.time_history.channels.size()));
  for (const auto& c : r.time_history.channels) {
    w.str(c.name);
    w.str(c.unit);
    w.str(c.description);
    w.f64s(c.values);
  }
  return w.take();
}

CaseRecord deserialize(std::span<const char> bytes) {
  ByteReader in(bytes);
  if (in.u32() != kRecordMagic) throw RecordFormatError("not a planetwear case record (bad magic)");
  if (const auto v = in.u32(); v != kRecordVersion)
    throw RecordFormatError("case record format version " + std::to_string(v) + ", expected " +
                            std::to_string(kRecordVersion));
  auto count = [&](const char* what) {
    const std::int64_t n = in.i64();
    if (n < 0 || n > (std::int64_t{1} << 32)) throw RecordFormatError(std::string("bad ") + what + " count");
    return static_cast<std::size_t>(n);
  };
  CaseRecord r;
  r.index = in.i64();
  const std::uint32_t status = in.u32();
  if (status > static_cast<std::uint32_t>(CaseStatus::Failed)) throw RecordFormatError("bad case status");
  r.status = static_cast<CaseStatus>(status);
  r.message = in.str();
  r.wall_time_s = in.f64();
  r.rank = static_cast<int>(in.i64());
  for (std::size_t k = count("scalar"); k > 0; --k) {
    NamedScalar s;
    s.name = in.str();
    s.unit = in.str();
    s.description = in.str();
    s.value = in.f64();
    r.scalars.push_back(std::move(s));
  }
  for (std::size_t k = count("wear"); k > 0; --k) {
    FinalWear f;
    f.family = in.str();
    f.distance_from_pitch_point_m = in.f64s();
    f.mean_depth_m = in.f64s();
    f.max_depth_m = in.f64s();
    if (f.mean_depth_m.size() != f.distance_from_pitch_point_m.size() ||
        f.max_depth_m.size() != f.distance_from_pitch_point_m.size())
      throw RecordFormatError("wear profile of '" + f.family + "' has inconsistent lengths");
    r.wear.push_back(std::move(f));
  }
  for (std::size_t k = count("spectrum"); k > 0; --k) {
    SpectrumRecord s;
    s.channel = in.str();
    s.unit = in.str();
    s.frequency_Hz = in.f64s();
    s.amplitude = in.f64s();
    if (s.frequency_Hz.size() != s.amplitude.size())
      throw RecordFormatError("spectrum '" + s.channel + "' has inconsistent lengths");
    r.spectra.push_back(std::move(s));
  }
  r.time_history.time_s = in.f64s();
  for (std::size_t k = count("channel"); k > 0; --k) {
    model::Channel c;
    c.name = in.str();
    c.unit = in.str();
    c.description = in.str();
    c.values = in.f64s();
    if (c.values.size() != r.time_history.time_s.size())
      throw RecordFormatError("time history '" + c.name + "' is not as long as its time axis");
    r.time_history.channels.push_back(std::move(c));
  }
  if (!in.at_end()) throw RecordFormatError("trailing bytes after the case record");
  return r;
}

} // namespace pw::sweep
