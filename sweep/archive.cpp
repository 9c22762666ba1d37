#include "archive.hpp"

#include "io/config_toml.hpp"
#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"
#include "io/result_writer.hpp"


#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

namespace pw::sweep {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

/// Names of every dataset below `group` (relative, '/'-separated), in name order.
void list_datasets(const io::H5File& f, const std::string& group, const std::string& prefix,
                   std::vector<std::string>& out) {
  for (const auto& m : f.members(group)) {
    const std::string path = group + "/" + m;
    const std::string rel = prefix.empty() ? m : prefix + "/" + m;
    if (f.is_group(path)) list_datasets(f, path, rel, out);
    else out.push_back(rel);
  }
}

struct ScalarInfo {
  std::string unit, description;
};

/// Union of names over records, with the unit/description of the first case having it.
template <class Get>
std::map<std::string, ScalarInfo> union_of(std::span<const std::shared_ptr<const CaseRecord>> records, Get get) {
  std::map<std::string, ScalarInfo> names;
  for (const auto& r : records)
    if (r && r->status == CaseStatus::Done) get(*r, names);
  return names;
}

/// Writes /case (the case index, as /design/case) and makes it the dimension
/// scale of the first (case) dimension of every dataset of /design and
/// /results, so h5py (dataset.dims[0][0]) and netCDF readers see the join key
/// of the design and the results. It sits at the root because netCDF readers
/// (xarray's h5netcdf engine) look a dimension up in the group of the
/// dataset and its ancestors only. The second dimension of the padded 2-D
/// results gets a label only ("bin", "sample", "element"): its coordinate
/// (frequency, time, position) differs from case to case, and a dimension
/// scale is 1-D.
void write_case_scale(io::H5File& f, std::span<const int> case_index) {
  f.write("/case", case_index);
  f.set_attribute("/case", "description",
                  "case index (= /design/case): the dimension scale of the case dimension of every /design and "
                  "/results dataset");
  f.make_dimension_scale("/case", "case");
  std::vector<std::string> datasets;
  for (const std::string group : {"design", "results"}) {
    std::vector<std::string> below;
    list_datasets(f, "/" + group, "", below);
    for (const auto& name : below) datasets.push_back("/" + group + "/" + name);
  }
  for (const auto& path : datasets) {
    f.attach_dimension_scale(path, "/case", 0);
    f.set_dimension_label(path, 0, "case");
  }
}

io::DatasetOptions compressed() {
  io::DatasetOptions o;
  o.compress = true;
  return o;
}

/// What every part of the archive is written from: the campaign, one record per case
/// (null: not run) and which cases are done.
struct ArchiveRows {
  const Campaign& c;
  std::span<const std::shared_ptr<const CaseRecord>> records;
  std::size_t n;
  bool is_done(std::size_t i) const { return records[i] && records[i]->status == CaseStatus::Done; }
};

/// Root attributes (provenance, case counts) and the campaign's inputs.
void write_provenance(io::H5File& f, const ArchiveRows& rows, const ArchiveRunInfo& info) {
  const Campaign& c = rows.c;
  const std::size_t n = rows.n;
  std::size_t done = 0, failed = 0;
  for (const auto& r : rows.records) {
    if (r && r->status == CaseStatus::Done) ++done;
    if (r && r->status == CaseStatus::Failed) ++failed;
  }
  // Root: provenance.
  f.set_attribute("/", "format", kArchiveFormat);
  f.set_attribute("/", "format_version", kArchiveFormatVersion);
  f.set_attribute("/", "software_version", io::software_version());
  f.set_attribute("/", "build_flags", io::build_flags());
  f.set_attribute("/", "created_utc", utc_now());
  f.set_attribute("/", "units_convention", "SI");
  f.set_attribute("/", "cases", static_cast<std::int64_t>(n));
  f.set_attribute("/", "cases_done", static_cast<std::int64_t>(done));
  f.set_attribute("/", "cases_failed", static_cast<std::int64_t>(failed));
  f.set_attribute("/", "cases_pending", static_cast<std::int64_t>(n - done - failed));
  f.set_attribute("/", "complete", static_cast<std::int64_t>(done + failed == n ? 1 : 0));
  f.set_attribute("/", "mpi_ranks", static_cast<std::int64_t>(info.mpi_ranks));
  f.set_attribute("/", "case_begin", static_cast<std::int64_t>(info.case_begin));
  f.set_attribute("/", "case_end", static_cast<std::int64_t>(info.case_end));

  // Campaign inputs.
  f.write_string("/campaign/toml", c.text);
  f.set_attribute("/campaign/toml", "description", "the campaign file, verbatim");
  f.write_string("/campaign/base_config_toml", io::to_toml(c.base));
  f.set_attribute("/campaign/base_config_toml", "description",
                  "the base case fully resolved ([base] config + [base.set]); a case's configuration is this plus "
                  "its factor values as --set overrides");
  if (c.design.type == DesignType::List) {
    f.write_string("/campaign/list_csv", c.design.list_text);
    f.set_attribute("/campaign/list_csv", "description", "the case list of the design, verbatim");
  }
  f.set_attribute("/campaign", "name", c.name);
  f.set_attribute("/campaign", "description", c.description);
  f.set_attribute("/campaign", "campaign_file", c.file.string());
  f.set_attribute("/campaign", "base_config_file", c.base_config_file.string());
  f.set_attribute("/campaign", "design_type", to_string(c.design.type));
  f.set_attribute("/campaign", "input_hash", hex64(c.input_hash));
  f.set_attribute("/campaign", "design_hash", hex64(c.design_hash));
  f.set_attribute("/campaign", "seed", static_cast<std::int64_t>(c.design.seed));
  f.set_attribute("/campaign", "points", static_cast<std::int64_t>(c.design.points));
  f.set_attribute("/campaign", "samples", static_cast<std::int64_t>(c.design.samples));
  f.set_attribute("/campaign", "base_samples", static_cast<std::int64_t>(c.design.base_samples));
  f.set_attribute("/campaign", "time_history_decimation", static_cast<std::int64_t>(c.output.time_history_decimation));
  f.set_attribute("/campaign", "spectrum_max_frequency_Hz", c.output.spectrum_max_frequency_Hz);
  std::string keys;
  for (const auto& fa : c.factors) keys += (keys.empty() ? "" : ",") + fa.key;
  f.set_attribute("/campaign", "factors", keys);

}

/// The numeric columns of /design; returns the case indices (for the case scale).
std::vector<int> write_design_numbers(io::H5File& f, const ArchiveRows& rows) {
  const Campaign& c = rows.c;
  const std::size_t n = rows.n;
  const auto& records = rows.records;
  // Design table: numeric columns here, string columns below.
  std::vector<int> case_index(n), rank(n), row(n);
  std::vector<double> wall(n, kNaN);
  for (std::size_t i = 0; i < n; ++i) {
    case_index[i] = static_cast<int>(i);
    row[i] = static_cast<int>(c.cases[i].row);
    rank[i] = records[i] ? records[i]->rank : -1;
    if (records[i]) wall[i] = records[i]->wall_time_s;
  }
  std::string columns = "case";
  f.write("/design/case", std::span<const int>(case_index));
  f.set_attribute("/design/case", "description", "case index (row of every /results dataset)");
  for (std::size_t k = 0; k < c.factors.size(); ++k) {
    const Factor& fa = c.factors[k];
    std::vector<double> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = c.cases[i].values[k];
    const std::string p = "/design/" + fa.key;
    f.write(p, std::span<const double>(v));
    f.set_units(p, fa.unit);
    f.set_attribute(p, "description", "factor " + std::to_string(k) + ": configuration key " + fa.key);
    f.set_attribute(p, "scale", to_string(fa.scale));
    if (fa.min) f.set_attribute(p, "min", *fa.min);
    if (fa.max) f.set_attribute(p, "max", *fa.max);
    const Distribution& dist = fa.distribution;
    f.set_attribute(p, "distribution", std::string(to_string(dist.kind)));
    if (dist.kind == DistributionKind::Normal || dist.kind == DistributionKind::LogNormal) {
      f.set_attribute(p, "mean", dist.mean);
      f.set_attribute(p, "std_dev", dist.std_dev);
    }
    if (dist.kind == DistributionKind::Triangular) f.set_attribute(p, "mode", dist.mode);
    columns += "," + fa.key;
  }
  f.write("/design/wall_time", std::span<const double>(wall));
  f.set_units("/design/wall_time", "s");
  f.set_attribute("/design/wall_time", "description", "wall time to simulate and summarize the case; NaN = not run");
  f.write("/design/rank", std::span<const int>(rank));
  f.set_attribute("/design/rank", "description", "MPI rank that ran the case; -1 = not run");
  f.write("/design/sample_row", std::span<const int>(row));
  f.set_attribute("/design/sample_row", "description",
                  "saltelli designs: row j of the sample matrices A, B, AB_i; -1 for other designs");
  columns += ",status,message,wall_time,rank,sample_role,sample_row";
  f.set_attribute("/design", "columns", columns);
  f.set_attribute("/design", "description",
                  "one row per case; pandas: pd.DataFrame({k: (v.asstr()[:] if v.dtype.kind == 'O' else v[:]) "
                  "for k, v in h5py.File(path)['design'].items()})");

  return case_index;
}

/// /results/scalars: one NaN-padded column per scalar any case has.
void write_scalars(io::H5File& f, const ArchiveRows& rows) {
  const std::size_t n = rows.n;
  const auto& records = rows.records;
  auto is_done = [&](std::size_t i) { return rows.is_done(i); };
  // Scalars.
  f.create_group("/results/scalars");
  f.set_attribute("/results", "description", "per-case results, first index = case; NaN where a case is not done");
  const auto scalar_names = union_of(records, [](const CaseRecord& r, std::map<std::string, ScalarInfo>& m) {
    for (const auto& s : r.scalars) m.try_emplace(s.name, ScalarInfo{s.unit, s.description});
  });
  for (const auto& [name, si] : scalar_names) {
    std::vector<double> v(n, kNaN);
    for (std::size_t i = 0; i < n; ++i)
      if (is_done(i))
        if (const NamedScalar* s = records[i]->find_scalar(name)) v[i] = s->value;
    const std::string p = "/results/scalars/" + name;
    f.write(p, std::span<const double>(v));
    f.set_units(p, si.unit);
    f.set_attribute(p, "description", si.description);
  }

}

/// /results/wear/<family>: final profiles per flank family.
void write_wear(io::H5File& f, const ArchiveRows& rows) {
  const std::size_t n = rows.n;
  const auto& records = rows.records;
  auto is_done = [&](std::size_t i) { return rows.is_done(i); };
  // Wear: final profiles per flank family.
  f.create_group("/results/wear");
  const auto families = union_of(records, [](const CaseRecord& r, std::map<std::string, ScalarInfo>& m) {
    for (const auto& w : r.wear) m.try_emplace(w.family, ScalarInfo{"m", ""});
  });
  for (const auto& [family, unused] : families) {
    (void)unused;
    std::size_t width = 0;
    std::vector<const FinalWear*> of(n, nullptr);
    for (std::size_t i = 0; i < n; ++i)
      if (is_done(i))
        for (const auto& w : records[i]->wear)
          if (w.family == family) {
            of[i] = &w;
            width = std::max(width, w.mean_depth_m.size());
          }
    std::vector<double> mean(n * width, kNaN), max(n * width, kNaN), x(n * width, kNaN);
    std::vector<int> elements(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (of[i]) {
        elements[i] = static_cast<int>(of[i]->mean_depth_m.size());
        std::copy(of[i]->mean_depth_m.begin(), of[i]->mean_depth_m.end(), mean.begin() + i * width);
        std::copy(of[i]->max_depth_m.begin(), of[i]->max_depth_m.end(), max.begin() + i * width);
        std::copy(of[i]->distance_from_pitch_point_m.begin(), of[i]->distance_from_pitch_point_m.end(),
                  x.begin() + i * width);
      }
    const std::string g = "/results/wear/" + family;
    f.write_2d(g + "/depth_final", mean, n, width, compressed());
    f.set_dimension_label(g + "/depth_final", 1, "element");
    f.set_units(g + "/depth_final", "m");
    f.set_attribute(g + "/depth_final", "description", "final wear depth per element, averaged over the teeth");
    f.write_2d(g + "/depth_final_max", max, n, width, compressed());
    f.set_dimension_label(g + "/depth_final_max", 1, "element");
    f.set_units(g + "/depth_final_max", "m");
    f.set_attribute(g + "/depth_final_max", "description", "final wear depth per element, maximum over the teeth");
    f.write_2d(g + "/distance_from_pitch_point", x, n, width, compressed());
    f.set_dimension_label(g + "/distance_from_pitch_point", 1, "element");
    f.set_units(g + "/distance_from_pitch_point", "m");
    f.set_attribute(g + "/distance_from_pitch_point", "description",
                    "signed distance of each element centre from the pitch point along the line of action, "
                    "positive towards this gear's tip");
    f.write(g + "/elements", std::span<const int>(elements));
    f.set_attribute(g + "/elements", "description", "elements of this case (valid columns); 0 = no wear data");
  }

}

/// /results/spectra: one frequency axis per case, shared by its channels.
void write_spectra(io::H5File& f, const ArchiveRows& rows) {
  const std::size_t n = rows.n;
  const auto& records = rows.records;
  auto is_done = [&](std::size_t i) { return rows.is_done(i); };
  // Spectra: one frequency axis per case, shared by the channels.
  f.create_group("/results/spectra");
  const auto channels = union_of(records, [](const CaseRecord& r, std::map<std::string, ScalarInfo>& m) {
    for (const auto& s : r.spectra) m.try_emplace(s.channel, ScalarInfo{s.unit, ""});
  });
  if (!channels.empty()) {
    std::size_t width = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (is_done(i))
        for (const auto& s : records[i]->spectra) width = std::max(width, s.amplitude.size());
    std::vector<double> freq(n * width, kNaN);
    std::vector<int> bins(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (!is_done(i) || records[i]->spectra.empty()) continue;
      const auto& axis = records[i]->spectra.front().frequency_Hz;
      for (const auto& s : records[i]->spectra)
        if (s.frequency_Hz != axis)
          throw std::invalid_argument("write_archive: spectra of case " + std::to_string(i) +
                                      " lie on different frequency axes");
      bins[i] = static_cast<int>(axis.size());
      std::copy(axis.begin(), axis.end(), freq.begin() + i * width);
    }
    f.write_2d("/results/spectra/frequency", freq, n, width, compressed());
    f.set_dimension_label("/results/spectra/frequency", 1, "bin");
    f.set_units("/results/spectra/frequency", "Hz");
    f.set_attribute("/results/spectra/frequency", "description", "frequency of each bin, per case");
    f.write("/results/spectra/bins", std::span<const int>(bins));
    f.set_attribute("/results/spectra/bins", "description", "bins of this case (valid columns); 0 = not done");
    for (const auto& [channel, ci] : channels) {
      std::vector<double> amp(n * width, kNaN);
      for (std::size_t i = 0; i < n; ++i)
        if (is_done(i))
          for (const auto& s : records[i]->spectra)
            if (s.channel == channel) std::copy(s.amplitude.begin(), s.amplitude.end(), amp.begin() + i * width);
      const std::string p = "/results/spectra/" + channel;
      f.write_2d(p, amp, n, width, compressed());
      f.set_dimension_label(p, 1, "bin");
      f.set_units(p, ci.unit);
      f.set_attribute(p, "description", "amplitude spectrum of " + channel +
                                            ": Hann window, peak amplitude, single-sided, coherent-gain corrected");
    }
  }

}

/// /results/time_history: the decimated time histories.
void write_time_histories(io::H5File& f, const ArchiveRows& rows) {
  const Campaign& c = rows.c;
  const std::size_t n = rows.n;
  const auto& records = rows.records;
  auto is_done = [&](std::size_t i) { return rows.is_done(i); };
  // Decimated time histories.
  const auto th_channels = union_of(records, [](const CaseRecord& r, std::map<std::string, ScalarInfo>& m) {
    for (const auto& ch : r.time_history.channels) m.try_emplace(ch.name, ScalarInfo{ch.unit, ch.description});
  });
  if (!th_channels.empty()) {
    std::size_t width = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (is_done(i)) width = std::max(width, records[i]->time_history.time_s.size());
    std::vector<double> time(n * width, kNaN);
    std::vector<int> samples(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (is_done(i)) {
        const auto& t = records[i]->time_history.time_s;
        samples[i] = static_cast<int>(t.size());
        std::copy(t.begin(), t.end(), time.begin() + i * width);
      }
    f.write_2d("/results/time_history/time", time, n, width, compressed());
    f.set_dimension_label("/results/time_history/time", 1, "sample");
    f.set_units("/results/time_history/time", "s");
    f.set_attribute("/results/time_history/time", "description", "sample times, per case");
    f.write("/results/time_history/samples", std::span<const int>(samples));
    f.set_attribute("/results/time_history/samples", "description", "samples of this case (valid columns)");
    f.set_attribute("/results/time_history", "decimation", static_cast<std::int64_t>(c.output.time_history_decimation));
    for (const auto& [name, ci] : th_channels) {
      std::vector<double> v(n * width, kNaN);
      for (std::size_t i = 0; i < n; ++i)
        if (is_done(i))
          for (const auto& ch : records[i]->time_history.channels)
            if (ch.name == name) std::copy(ch.values.begin(), ch.values.end(), v.begin() + i * width);
      const std::string p = "/results/time_history/" + name;
      f.write_2d(p, v, n, width, compressed());
      f.set_dimension_label(p, 1, "sample");
      f.set_units(p, ci.unit);
      f.set_attribute(p, "description", ci.description);
    }
  }
}

/// The string columns of /design.
void write_design_strings(io::H5File& f, const ArchiveRows& rows) {
  const Campaign& c = rows.c;
  const std::size_t n = rows.n;
  const auto& records = rows.records;
  // String columns of /design (variable-length UTF-8, as h5py writes them).
  std::vector<std::string> status(n), message(n), role(n);
  for (std::size_t i = 0; i < n; ++i) {
    status[i] = std::string(to_string(records[i] ? records[i]->status : CaseStatus::Pending));
    message[i] = records[i] ? records[i]->message : "";
    role[i] = c.cases[i].role;
  }
  f.write_strings("/design/status", status);
  f.set_attribute("/design/status", "description", "pending, done or failed");
  f.write_strings("/design/message", message);
  f.set_attribute("/design/message", "description",
                  "failed: the reason; done: a note such as why wear stopped early; else empty");
  f.write_strings("/design/sample_role", role);
  f.set_attribute("/design/sample_role", "description",
                  "saltelli designs: A, B or AB_<i> (A with factor i from B); empty for other designs");
}

} // namespace

void write_archive(const std::filesystem::path& path, const Campaign& c,
                   std::span<const std::shared_ptr<const CaseRecord>> records, const ArchiveRunInfo& info) {
  const std::size_t n = c.cases.size();
  if (records.size() != n)
    throw std::invalid_argument("write_archive: " + std::to_string(records.size()) + " records for " +
                                std::to_string(n) + " cases");
  for (std::size_t i = 0; i < n; ++i)
    if (records[i] && records[i]->index != static_cast<std::int64_t>(i))
      throw std::invalid_argument("write_archive: record of case " + std::to_string(records[i]->index) +
                                  " at position " + std::to_string(i));
  const ArchiveRows rows{c, records, n};
  io::H5File f = io::H5File::create(path);
  write_provenance(f, rows, info);
  const std::vector<int> case_index = write_design_numbers(f, rows);
  write_scalars(f, rows);
  write_wear(f, rows);
  write_spectra(f, rows);
  write_time_histories(f, rows);
  write_design_strings(f, rows);
  write_case_scale(f, case_index);
  f.close();
}

ArchiveContents read_archive(const std::filesystem::path& path) {
  ArchiveContents out;
  const io::H5File f = io::H5File::open(path);
  if (!f.has_attribute("/", "format") || f.read_string_attribute("/", "format") != kArchiveFormat)
    throw io::IoError(path.string() + ": not a planetwear campaign archive (root attribute format is not \"" +
                      std::string(kArchiveFormat) + "\")");
  if (const auto v = f.read_int_attribute("/", "format_version"); v != kArchiveFormatVersion)
    throw io::IoError(path.string() + ": campaign archive format version " + std::to_string(v) +
                      ", this program reads version " + std::to_string(kArchiveFormatVersion));
  const std::vector<std::string> status = f.read_strings("/design/status");
  const std::vector<std::string> message = f.read_strings("/design/message");
  out.input_hash = f.read_string_attribute("/campaign", "input_hash");
  out.design_hash = f.read_string_attribute("/campaign", "design_hash");
  const std::size_t n = status.size();
  out.cases = n;
  out.case_begin = 0;
  out.case_end = n;
  if (f.has_attribute("/", "case_begin") && f.has_attribute("/", "case_end")) {
    out.case_begin = static_cast<std::size_t>(f.read_int_attribute("/", "case_begin"));
    out.case_end = static_cast<std::size_t>(f.read_int_attribute("/", "case_end"));
  }
  const auto wall = f.read_doubles("/design/wall_time");
  const auto rank = f.read_ints("/design/rank");
  if (message.size() != n || wall.size() != n || rank.size() != n)
    throw io::IoError(path.string() + ": /design columns of different lengths");

  std::vector<CaseRecord> records(n);
  std::vector<bool> done(n, false), keep(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    CaseStatus s;
    try {
      s = case_status_from(status[i]);
    } catch (const std::invalid_argument& e) {
      throw io::IoError(path.string() + ": /design/status of case " + std::to_string(i) + ": " + e.what());
    }
    records[i].index = static_cast<std::int64_t>(i);
    records[i].status = s;
    records[i].message = message[i];
    records[i].wall_time_s = wall[i];
    records[i].rank = rank[i];
    done[i] = s == CaseStatus::Done;
    keep[i] = s != CaseStatus::Pending;
  }
  auto check_rows = [&](const std::string& p, std::size_t values, std::size_t& width) {
    const auto shape = f.shape(p);
    if (shape.empty() || shape[0] != n || (shape.size() == 2 ? shape[0] * shape[1] : shape[0]) != values)
      throw io::IoError(path.string() + ": '" + p + "' does not have one row per case");
    width = shape.size() == 2 ? shape[1] : 1;
  };

  std::vector<std::string> names;
  list_datasets(f, "/results/scalars", "", names);
  for (const auto& name : names) {
    const std::string p = "/results/scalars/" + name;
    const auto v = f.read_doubles(p);
    std::size_t w = 0;
    check_rows(p, v.size(), w);
    const std::string unit = f.read_string_attribute(p, "unit"), description = f.read_string_attribute(p, "description");
    for (std::size_t i = 0; i < n; ++i)
      if (done[i]) records[i].scalars.push_back({name, unit, description, v[i]});
  }

  std::vector<std::string> wear_sets;
  list_datasets(f, "/results/wear", "", wear_sets);
  for (const auto& set : wear_sets) {
    if (!set.ends_with("/elements")) continue;
    const std::string family = set.substr(0, set.size() - std::string("/elements").size());
    const std::string g = "/results/wear/" + family;
    const auto elements = f.read_ints(g + "/elements");
    const auto mean = f.read_doubles(g + "/depth_final"), max = f.read_doubles(g + "/depth_final_max"),
               x = f.read_doubles(g + "/distance_from_pitch_point");
    std::size_t w = 0, w2 = 0, w3 = 0;
    check_rows(g + "/depth_final", mean.size(), w);
    check_rows(g + "/depth_final_max", max.size(), w2);
    check_rows(g + "/distance_from_pitch_point", x.size(), w3);
    for (std::size_t i = 0; i < n; ++i) {
      if (!done[i] || elements.at(i) <= 0) continue;
      const auto e = static_cast<std::size_t>(elements[i]);
      if (e > w) throw io::IoError(path.string() + ": " + g + "/elements exceeds the dataset width");
      const auto at = static_cast<std::ptrdiff_t>(i * w);
      const auto end = at + static_cast<std::ptrdiff_t>(e);
      records[i].wear.push_back({family, {x.begin() + at, x.begin() + end}, {mean.begin() + at, mean.begin() + end},
                                 {max.begin() + at, max.begin() + end}});
    }
  }

  if (f.exists("/results/spectra/bins")) {
    const auto bins = f.read_ints("/results/spectra/bins");
    const auto freq = f.read_doubles("/results/spectra/frequency");
    std::size_t w = 0;
    check_rows("/results/spectra/frequency", freq.size(), w);
    std::vector<std::string> sets;
    list_datasets(f, "/results/spectra", "", sets);
    for (const auto& ch : sets) {
      if (ch == "bins" || ch == "frequency") continue;
      const std::string p = "/results/spectra/" + ch;
      const auto amp = f.read_doubles(p);
      std::size_t wa = 0;
      check_rows(p, amp.size(), wa);
      const std::string unit = f.read_string_attribute(p, "unit");
      for (std::size_t i = 0; i < n; ++i) {
        if (!done[i] || bins.at(i) <= 0) continue;
        const auto b = static_cast<std::size_t>(bins[i]);
        if (b > w || b > wa) throw io::IoError(path.string() + ": /results/spectra/bins exceeds the dataset width");
        records[i].spectra.push_back({ch, unit,
                                      {freq.begin() + static_cast<std::ptrdiff_t>(i * w),
                                       freq.begin() + static_cast<std::ptrdiff_t>(i * w + b)},
                                      {amp.begin() + static_cast<std::ptrdiff_t>(i * wa),
                                       amp.begin() + static_cast<std::ptrdiff_t>(i * wa + b)}});
      }
    }
  }

  if (f.exists("/results/time_history/samples")) {
    const auto samples = f.read_ints("/results/time_history/samples");
    const auto time = f.read_doubles("/results/time_history/time");
    std::size_t w = 0;
    check_rows("/results/time_history/time", time.size(), w);
    for (std::size_t i = 0; i < n; ++i)
      if (done[i] && samples.at(i) > 0) {
        const auto s = static_cast<std::size_t>(samples[i]);
        if (s > w) throw io::IoError(path.string() + ": /results/time_history/samples exceeds the dataset width");
        records[i].time_history.time_s.assign(time.begin() + static_cast<std::ptrdiff_t>(i * w),
                                              time.begin() + static_cast<std::ptrdiff_t>(i * w + s));
      }
    std::vector<std::string> sets;
    list_datasets(f, "/results/time_history", "", sets);
    for (const auto& ch : sets) {
      if (ch == "samples" || ch == "time") continue;
      const std::string p = "/results/time_history/" + ch;
      const auto v = f.read_doubles(p);
      std::size_t wc = 0;
      check_rows(p, v.size(), wc);
      const std::string unit = f.read_string_attribute(p, "unit"), description = f.read_string_attribute(p, "description");
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t s = records[i].time_history.time_s.size();
        if (!done[i] || s == 0) continue;
        records[i].time_history.channels.push_back(
            {ch, unit, description,
             {v.begin() + static_cast<std::ptrdiff_t>(i * wc), v.begin() + static_cast<std::ptrdiff_t>(i * wc + s)}});
      }
    }
  }

  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) out.records.push_back(std::move(records[i]));
  return out;
}

} // namespace pw::sweep
