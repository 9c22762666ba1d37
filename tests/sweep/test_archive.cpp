// The campaign archive and the journal: written records read back exactly
// (what --resume relies on), NaN rows for pending cases, the documented
// /design columns with units, and journal entries that are atomic,
// checksummed, campaign-specific and locked against a second run.
#include "sweep/archive.hpp"
#include "sweep/journal.hpp"

#include "core/error.hpp"
#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace pw::sweep {
namespace {

using pw::test::contains;
using pw::test::thrown;

Campaign three_speeds() {
  return parse_campaign(R"(
[[factors]]
key = "operating.input_speed_rpm"
unit = "rpm"
levels = [100.0, 200.0, 400.0]
[[factors]]
key = "stage.planet_count"
unit = "-"
levels = [3]
[design]
type = "full_factorial"
[output]
time_history_decimation = 2
)",
                        ".", "three.toml");
}

/// A done record with every kind of data; sizes depend on `k` so that the
/// archive pads shorter rows with NaN.
CaseRecord done_record(std::int64_t index, std::size_t k) {
  CaseRecord r;
  r.index = index;
  r.status = CaseStatus::Done;
  r.rank = static_cast<int>(index % 2);
  r.wall_time_s = 0.5 + static_cast<double>(index);
  r.scalars = {{"efficiency", "1", "eta", 0.9 + 0.01 * static_cast<double>(index)},
               {"sun_planet/0/acceleration_rms", "m/s^2", "rms", 3.0 * static_cast<double>(index)}};
  if (k == 3) r.scalars.push_back({"only_here", "N", "a scalar only this case has", 7.0});
  FinalWear w{"planet_0/sun_side", {}, {}, {}};
  for (std::size_t e = 0; e < k; ++e) {
    w.distance_from_pitch_point_m.push_back(1e-3 * static_cast<double>(e));
    w.mean_depth_m.push_back(1e-7 * static_cast<double>(e + index));
    w.max_depth_m.push_back(2e-7 * static_cast<double>(e + index));
  }
  r.wear.push_back(w);
  SpectrumRecord s1{"sun_planet/0/acceleration", "m/s^2", {}, {}}, s2{"planet_ring/0/acceleration", "m/s^2", {}, {}};
  for (std::size_t b = 0; b < k + 1; ++b) {
    s1.frequency_Hz.push_back(10.0 * static_cast<double>(b));
    s1.amplitude.push_back(static_cast<double>(b + index));
    s2.amplitude.push_back(0.5 * static_cast<double>(b));
  }
  s2.frequency_Hz = s1.frequency_Hz;
  r.spectra = {s1, s2};
  for (std::size_t t = 0; t < k; ++t) r.time_history.time_s.push_back(1e-3 * static_cast<double>(t));
  r.time_history.channels.push_back({"sun_planet/0/deflection", "m", "deflection", r.time_history.time_s});
  return r;
}

/// `back` (read from an archive) equals `original`: the same scalars (in
/// name order; scalars only other cases have are NaN) and identical wear,
/// spectra and time histories.
void expect_same(const CaseRecord& back, const CaseRecord& original) {
  for (const auto& s : original.scalars) {
    const NamedScalar* t = back.find_scalar(s.name);
    ASSERT_NE(t, nullptr) << s.name;
    EXPECT_EQ(t->value, s.value) << s.name;
    EXPECT_EQ(t->unit, s.unit) << s.name;
    EXPECT_EQ(t->description, s.description) << s.name;
  }
  for (const auto& t : back.scalars)
    if (!original.find_scalar(t.name)) {
      EXPECT_TRUE(std::isnan(t.value)) << t.name;
    }
  // The archive keeps spectra, wear families and channels in name order.
  auto normalized = [](CaseRecord r) {
    r.scalars.clear();
    std::sort(r.spectra.begin(), r.spectra.end(), [](const auto& a, const auto& b) { return a.channel < b.channel; });
    std::sort(r.wear.begin(), r.wear.end(), [](const auto& a, const auto& b) { return a.family < b.family; });
    auto& ch = r.time_history.channels;
    std::sort(ch.begin(), ch.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    return r;
  };
  const CaseRecord x = normalized(back), y = normalized(original);
  EXPECT_EQ(serialize(x), serialize(y)) << "case " << back.index;
}

TEST(Archive, RecordsReadBackExactlyAndPendingRowsAreNaN) {
  test::TempDir dir;
  const Campaign c = three_speeds();
  std::vector<std::shared_ptr<const CaseRecord>> records(3);
  records[0] = std::make_shared<const CaseRecord>(done_record(0, 3));
  records[2] = std::make_shared<const CaseRecord>(failed_record(2, "diverged at t = 0.1 s"));
  write_archive(dir / "a.h5", c, records, {2});

  const ArchiveContents back = read_archive(dir / "a.h5");
  EXPECT_EQ(back.cases, 3u);
  EXPECT_EQ(back.input_hash, hex64(c.input_hash));
  EXPECT_EQ(back.design_hash, hex64(c.design_hash));
  ASSERT_EQ(back.records.size(), 2u);
  expect_same(back.records[0], *records[0]);
  EXPECT_EQ(back.records[1].status, CaseStatus::Failed);
  EXPECT_EQ(back.records[1].message, "diverged at t = 0.1 s");

  const io::H5File f = io::H5File::open(dir / "a.h5");
  EXPECT_EQ(f.read_string_attribute("/", "format"), "planetwear.campaign");
  EXPECT_EQ(f.read_int_attribute("/", "complete"), 0);
  EXPECT_EQ(f.read_int_attribute("/", "cases_pending"), 1);
  EXPECT_EQ(f.read_doubles("/design/operating.input_speed_rpm"), (std::vector<double>{100, 200, 400}));
  EXPECT_EQ(f.read_string_attribute("/design/operating.input_speed_rpm", "unit"), "rpm");
  EXPECT_EQ(f.read_string_attribute("/design/operating.input_speed_rpm", "distribution"), "uniform");
  EXPECT_EQ(f.read_ints("/design/case"), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(f.read_ints("/design/rank"), (std::vector<int>{0, -1, -1}));
  EXPECT_EQ(f.read_string_attribute("/design/wall_time", "unit"), "s");
  const auto eff = f.read_doubles("/results/scalars/efficiency");
  EXPECT_EQ(eff[0], 0.9);
  EXPECT_TRUE(std::isnan(eff[1]) && std::isnan(eff[2]));
  EXPECT_EQ(f.read_string_attribute("/results/scalars/sun_planet/0/acceleration_rms", "unit"), "m/s^2");
  EXPECT_EQ(f.shape("/results/wear/planet_0/sun_side/depth_final"), (std::vector<std::size_t>{3, 3}));
  EXPECT_EQ(f.shape("/results/spectra/sun_planet/0/acceleration"), (std::vector<std::size_t>{3, 4}));
  EXPECT_EQ(f.read_string_attribute("/results/spectra/frequency", "unit"), "Hz");
  EXPECT_EQ(f.read_string(std::string("/campaign/toml")), c.text);
}

/// Every dataset below `group` (absolute paths).
void collect_datasets(const io::H5File& f, const std::string& group, std::vector<std::string>& out) {
  for (const auto& m : f.members(group)) {
    const std::string path = group + "/" + m;
    if (f.is_group(path)) collect_datasets(f, path, out);
    else out.push_back(path);
  }
}

// docs/archive-format.md, "Conventions": `units` beside `unit`, /case (at the
// root, = /design/case) the dimension scale of the case dimension of every
// /design and /results dataset, the second dimension of the padded results
// labelled.
TEST(Archive, UnitsAndTheCaseDimensionScaleFollowTheCfConventions) {
  test::TempDir dir;
  const Campaign c = three_speeds();
  std::vector<std::shared_ptr<const CaseRecord>> records(3);
  records[0] = std::make_shared<const CaseRecord>(done_record(0, 3));
  records[1] = std::make_shared<const CaseRecord>(done_record(1, 2));
  write_archive(dir / "cf.h5", c, records, {1});

  const io::H5File f = io::H5File::open(dir / "cf.h5");
  EXPECT_TRUE(f.is_dimension_scale("/case"));
  EXPECT_EQ(f.read_ints("/case"), f.read_ints("/design/case"));
  std::vector<std::string> datasets;
  collect_datasets(f, "/design", datasets);
  collect_datasets(f, "/results", datasets);
  ASSERT_GT(datasets.size(), 10u);
  for (const auto& p : datasets) {
    if (f.has_attribute(p, "unit")) {
      EXPECT_EQ(f.read_string_attribute(p, "units"), f.read_string_attribute(p, "unit")) << p;
    }
    EXPECT_EQ(f.dimension_scales(p, 0), std::vector<std::string>{"/case"}) << p;
    EXPECT_EQ(f.dimension_label(p, 0), "case") << p;
  }
  EXPECT_EQ(f.dimension_label("/results/spectra/sun_planet/0/acceleration", 1), "bin");
  EXPECT_EQ(f.dimension_label("/results/spectra/frequency", 1), "bin");
  EXPECT_EQ(f.dimension_label("/results/time_history/time", 1), "sample");
  EXPECT_EQ(f.dimension_label("/results/wear/planet_0/sun_side/depth_final", 1), "element");
  EXPECT_EQ(f.read_string_attribute("/results/scalars/efficiency", "units"), "1");
  // The scale changes nothing a resume reads back.
  const ArchiveContents back = read_archive(dir / "cf.h5");
  ASSERT_EQ(back.records.size(), 2u);
  expect_same(back.records[1], *records[1]);
}

TEST(Archive, RowsOfDifferentLengthsArePaddedAndRoundTrip) {
  test::TempDir dir;
  const Campaign c = three_speeds();
  std::vector<std::shared_ptr<const CaseRecord>> records = {std::make_shared<const CaseRecord>(done_record(0, 2)),
                                                            std::make_shared<const CaseRecord>(done_record(1, 5)),
                                                            std::make_shared<const CaseRecord>(done_record(2, 3))};
  write_archive(dir / "a.h5", c, records, {1});
  const ArchiveContents back = read_archive(dir / "a.h5");
  ASSERT_EQ(back.records.size(), 3u);
  // Case 2 alone has "only_here"; after reading every done case carries every
  // scalar (NaN where it had none), which writes the same archive again.
  EXPECT_TRUE(std::isnan(back.records[0].find_scalar("only_here")->value));
  std::vector<std::shared_ptr<const CaseRecord>> again;
  for (const auto& r : back.records) again.push_back(std::make_shared<const CaseRecord>(r));
  write_archive(dir / "b.h5", c, again, {1});
  const io::H5File a = io::H5File::open(dir / "a.h5"), b = io::H5File::open(dir / "b.h5");
  for (const char* p : {"/results/scalars/only_here", "/results/scalars/efficiency",
                        "/results/wear/planet_0/sun_side/depth_final", "/results/wear/planet_0/sun_side/depth_final_max",
                        "/results/spectra/frequency", "/results/spectra/planet_ring/0/acceleration",
                        "/results/time_history/time", "/results/time_history/sun_planet/0/deflection"}) {
    const auto x = a.read_doubles(p), y = b.read_doubles(p);
    ASSERT_EQ(x.size(), y.size()) << p;
    for (std::size_t k = 0; k < x.size(); ++k)
      EXPECT_TRUE(x[k] == y[k] || (std::isnan(x[k]) && std::isnan(y[k]))) << p << "[" << k << "]";
  }
  const auto depth = a.read_doubles("/results/wear/planet_0/sun_side/depth_final");  // 3 x 5
  EXPECT_EQ(depth[0], 0.0);
  EXPECT_TRUE(std::isnan(depth[2]));  // case 0 has 2 elements
  EXPECT_EQ(a.read_ints("/results/wear/planet_0/sun_side/elements"), (std::vector<int>{2, 5, 3}));
  expect_same(back.records[1], *records[1]);
}

TEST(Archive, MisplacedRecordsAndForeignFilesAreErrors) {
  test::TempDir dir;
  const Campaign c = three_speeds();
  std::vector<std::shared_ptr<const CaseRecord>> records(3);
  records[1] = std::make_shared<const CaseRecord>(done_record(0, 2));
  EXPECT_THROW(write_archive(dir / "a.h5", c, records, {1}), std::invalid_argument);
  records.pop_back();
  EXPECT_THROW(write_archive(dir / "a.h5", c, records, {1}), std::invalid_argument);
  {
    auto f = io::H5File::create(dir / "other.h5");
    f.close();
  }
  EXPECT_THROW((void)read_archive(dir / "other.h5"), io::IoError);
  EXPECT_THROW((void)read_archive(dir / "missing.h5"), io::IoError);
}

TEST(Journal, EntriesRoundTripAndCorruptOnesAreSkipped) {
  test::TempDir dir;
  Journal j(dir / "r.h5.journal", 0x1234);
  j.lock();
  const CaseRecord a = done_record(4, 3), b = failed_record(1, "no");
  const auto pa = j.append(4, serialize(a));
  j.append(1, serialize(b));
  const auto pc = j.append(2, serialize(done_record(2, 2)));
  EXPECT_EQ(Journal::directory_for(dir / "r.h5"), dir / "r.h5.journal");
  EXPECT_TRUE(std::filesystem::exists(pa));
  // Corrupt entry 2 (one payload byte): skipped with a note, not fatal.
  {
    std::string text = test::read_text(pc);
    text[text.size() - 3] ^= 0x11;
    test::write_text(pc, text);
  }
  test::write_text(dir / "r.h5.journal" / "case-0000000009.rec.tmp", "half written");
  std::vector<std::string> notes;
  const auto entries = j.read(notes);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].record.index, 1);  // case order
  expect_same(entries[1].record, a);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_TRUE(contains(notes[0], "checksum mismatch"));
  j.clear();
  EXPECT_TRUE(j.read(notes).empty());
  j.remove_directory();
  EXPECT_FALSE(std::filesystem::exists(dir / "r.h5.journal"));
}

TEST(Journal, EntriesOfAnotherCampaignAreRefused) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "j");
  Journal(dir / "j", 1).append(0, serialize(done_record(0, 2)));
  std::vector<std::string> notes;
  const auto e = thrown<InputError>([&] { (void)Journal(dir / "j", 2).read(notes); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "journal entry of another campaign"));
}

TEST(Journal, SecondLockIsRefusedUntilTheFirstIsReleased) {
  test::TempDir dir;
  Journal first(dir / "j", 1), second(dir / "j", 1);
  first.lock();
  const auto e = thrown<io::IoError>([&] { second.lock(); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "another planetwear sweep is running"));
  first.unlock();
  EXPECT_NO_THROW(second.lock());
}

} // namespace
} // namespace pw::sweep
