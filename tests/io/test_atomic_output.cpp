// AtomicOutput: a run that fails leaves no file behind, and an existing file
// at the destination is replaced only by a complete new one.
#include "io/atomic_output.hpp"
#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"

#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace pw::io {
namespace {

using pw::test::contains;
using pw::test::thrown;

TEST(AtomicOutput, NoFileIsLeftWhenTheRunFailsBeforeCommit) {
  test::TempDir dir;
  const auto destination = dir / "run.h5";
  std::filesystem::path temp;
  const auto e = thrown<std::runtime_error>([&] {
    AtomicOutput out(destination);
    temp = out.temp_path();
    auto f = H5File::create(out.temp_path());
    f.write("/half", std::vector<double>{1, 2, 3});
    EXPECT_TRUE(std::filesystem::exists(temp));
    throw std::runtime_error("solver diverged");  // simulated failure mid-run
  });
  ASSERT_TRUE(e);
  EXPECT_FALSE(std::filesystem::exists(destination));
  EXPECT_FALSE(std::filesystem::exists(temp)) << "partial file left behind";
  EXPECT_EQ(dir.count(), 0u);
}

TEST(AtomicOutput, ExistingDestinationIsUntouchedUntilCommit) {
  test::TempDir dir;
  const auto destination = dir / "run.csv";
  test::write_text(destination, "previous results\n");

  AtomicOutput out(destination);
  test::write_text(out.temp_path(), "new results\n");
  EXPECT_EQ(test::read_text(destination), "previous results\n") << "destination changed before commit";
  EXPECT_TRUE(contains(out.temp_path().filename().string(), "run.csv.partial-"));
  EXPECT_EQ(out.temp_path().parent_path(), destination.parent_path()) << "temp file on another file system?";

  out.commit();
  EXPECT_TRUE(out.committed());
  EXPECT_EQ(test::read_text(destination), "new results\n");
  EXPECT_FALSE(std::filesystem::exists(out.temp_path()));
}

TEST(AtomicOutput, ExistingDestinationSurvivesAFailedRun) {
  test::TempDir dir;
  const auto destination = dir / "run.csv";
  test::write_text(destination, "previous results\n");
  {
    AtomicOutput out(destination);
    test::write_text(out.temp_path(), "half-written");
  }  // no commit: as if an exception unwound the stack
  EXPECT_EQ(test::read_text(destination), "previous results\n");
  EXPECT_EQ(dir.count(), 1u);
}

TEST(AtomicOutput, RefusesToOverwriteWhenNotAllowed) {
  test::TempDir dir;
  const auto destination = dir / "run.h5";
  test::write_text(destination, "keep me");
  const auto e = thrown<IoError>([&] { AtomicOutput out(destination, /*overwrite=*/false); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), destination.string()));

  // The destination appearing during the run is not clobbered either.
  const auto fresh = dir / "fresh.h5";
  AtomicOutput out(fresh, /*overwrite=*/false);
  test::write_text(out.temp_path(), "new");
  test::write_text(fresh, "written meanwhile");
  EXPECT_TRUE(thrown<IoError>([&] { out.commit(); }));
  EXPECT_EQ(test::read_text(fresh), "written meanwhile");
}

TEST(AtomicOutput, MissingDirectoryIsReportedBeforeAnyWork) {
  test::TempDir dir;
  const auto e = thrown<IoError>([&] { AtomicOutput out(dir / "no_such_dir" / "run.h5"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "no_such_dir"));
  EXPECT_TRUE(thrown<IoError>([&] { AtomicOutput out(dir.path()); })) << "a directory accepted as output file";
}

TEST(AtomicOutput, CommitWithoutOutputIsAnError) {
  test::TempDir dir;
  AtomicOutput out(dir / "run.h5");
  const auto e = thrown<IoError>([&] { out.commit(); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "was not written"));
  EXPECT_FALSE(std::filesystem::exists(dir / "run.h5"));
}

} // namespace
} // namespace pw::io
