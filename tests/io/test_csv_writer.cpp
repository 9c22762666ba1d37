// CSV time histories: "time_s,name [unit],..." header, exact numbers, channel
// selection, quoting, atomic file output.
#include "io/csv_writer.hpp"

#include "core/error.hpp"

#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

namespace pw::io {
namespace {

using pw::test::contains;
using pw::test::thrown;

model::SimulationResult result_with_two_channels() {
  model::SimulationResult r;
  r.time_s = {0.0, 0.1 + 0.2, 1e-300};
  r.channels = {{"sun_planet/0/deflection", "m", "", {1e-6, -2.5e-6, 1.0 / 3.0}},
                {"sun_planet/0/force", "N", "", {100.0, 200.5, -300.25}}};
  return r;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(CsvWriter, HeaderIsTimeThenNameWithUnitAndNumbersRoundTrip) {
  const auto r = result_with_two_channels();
  std::ostringstream out;
  write_csv(out, r);
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "time_s,sun_planet/0/deflection [m],sun_planet/0/force [N]");
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    std::istringstream row(lines[i + 1]);
    std::string cell;
    std::getline(row, cell, ',');
    EXPECT_EQ(std::strtod(cell.c_str(), nullptr), r.time_s[i]) << "time row " << i;
    for (const auto& c : r.channels) {
      std::getline(row, cell, ',');
      EXPECT_EQ(std::strtod(cell.c_str(), nullptr), c.values[i]) << c.name << " row " << i;
    }
  }
}

TEST(CsvWriter, SelectedChannelsAreWrittenInTheGivenOrder) {
  std::ostringstream out;
  write_csv(out, result_with_two_channels(), {{"sun_planet/0/force"}});
  EXPECT_EQ(lines_of(out.str())[0], "time_s,sun_planet/0/force [N]");
  EXPECT_EQ(lines_of(out.str())[1], "0,100");

  const auto e = thrown<InputError>([] {
    std::ostringstream sink;
    write_csv(sink, result_with_two_channels(), {{"sun_planet/9/force"}});
  });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "sun_planet/9/force");
  EXPECT_TRUE(contains(e->what(), "sun_planet/0/force"));  // lists what exists
}

TEST(CsvWriter, HeaderCellsWithCommasAreQuoted) {
  model::SimulationResult r;
  r.time_s = {0.0};
  r.channels = {{"a,b", "N \"peak\"", "", {1.0}}};
  std::ostringstream out;
  write_csv(out, r);
  EXPECT_EQ(lines_of(out.str())[0], "time_s,\"a,b [N \"\"peak\"\"]\"");
}

TEST(CsvWriter, FileIsWrittenAtomically) {
  test::TempDir dir;
  const auto path = dir / "run.csv";
  write_csv(path, result_with_two_channels());
  EXPECT_TRUE(contains(test::read_text(path), "time_s,sun_planet/0/deflection [m]"));

  // A failing write (unknown channel) leaves the previous file as it was.
  const std::string before = test::read_text(path);
  EXPECT_TRUE(thrown<InputError>([&] { write_csv(path, result_with_two_channels(), {{"nope"}}); }));
  EXPECT_EQ(test::read_text(path), before);
  EXPECT_EQ(dir.count(), 1u) << "temporary file left behind";
}

} // namespace
} // namespace pw::io
