// H5File: what is written reads back identically, with its attributes; groups
// appear on demand; failures are IoErrors naming file and object.
#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"

#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numeric>
#include <span>
#include <vector>

namespace pw::io {
namespace {

using pw::test::contains;
using pw::test::thrown;

TEST(H5File, DatasetsReadBackBitForBit) {
  test::TempDir dir;
  const auto path = dir / "data.h5";
  const std::vector<double> values{0.1 + 0.2, -1e-300, 1e300, std::numeric_limits<double>::quiet_NaN(), -0.0};
  const std::vector<double> matrix{1, 2, 3, 4, 5, 6};
  const std::vector<int> ints{-3, 0, 7, 2147483647};
  {
    auto f = H5File::create(path);
    f.write("/a/values", values);
    f.write_2d("/a/matrix", matrix, 2, 3);
    f.write("/b/ints", ints);
    f.write("/b/empty", std::vector<double>{});
    f.write_scalar("/b/scalar", 42.5);
    f.write_string("/b/text", "line 1\nline 2, unicode: \xc2\xb5m");
    f.close();
  }
  const auto f = H5File::open(path);
  const auto back = f.read_doubles("/a/values");
  ASSERT_EQ(back.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::isnan(values[i])) {
      EXPECT_TRUE(std::isnan(back[i]));
    } else {
      EXPECT_EQ(back[i], values[i]) << i;
      EXPECT_EQ(std::signbit(back[i]), std::signbit(values[i])) << i;
    }
  }
  EXPECT_EQ(f.shape("/a/matrix"), (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(f.read_doubles("/a/matrix"), matrix) << "row-major order lost";
  EXPECT_EQ(f.read_ints("/b/ints"), ints);
  EXPECT_TRUE(f.read_doubles("/b/empty").empty());
  EXPECT_EQ(f.shape("/b/empty"), (std::vector<std::size_t>{0}));
  EXPECT_EQ(f.read_scalar("/b/scalar"), 42.5);
  EXPECT_TRUE(f.shape("/b/scalar").empty()) << "scalar should be 0-d";
  EXPECT_EQ(f.read_string("/b/text"), "line 1\nline 2, unicode: \xc2\xb5m");
}

TEST(H5File, AttributesReadBackAndAreReplaced) {
  test::TempDir dir;
  const auto path = dir / "attrs.h5";
  {
    auto f = H5File::create(path);
    f.write("/g/x", std::vector<double>{1.0});
    f.set_attribute("/g/x", "unit", "m/s^2");
    f.set_attribute("/g/x", "unit", "m");  // replaces
    f.set_attribute("/g", "scale", 2.5);
    f.set_attribute("/", "count", std::int64_t{7});
    f.set_attribute("/", "units_convention", "SI");
    f.close();
  }
  const auto f = H5File::open(path);
  EXPECT_EQ(f.read_string_attribute("/g/x", "unit"), "m");
  EXPECT_EQ(f.read_double_attribute("/g", "scale"), 2.5);
  EXPECT_EQ(f.read_int_attribute("/", "count"), 7);
  EXPECT_EQ(f.read_string_attribute("/", "units_convention"), "SI");
  EXPECT_TRUE(f.has_attribute("/g/x", "unit"));
  EXPECT_FALSE(f.has_attribute("/g/x", "description"));
  EXPECT_FALSE(f.has_attribute("/missing", "unit"));
}

TEST(H5File, GroupsAreCreatedOnDemandAndListed) {
  test::TempDir dir;
  auto f = H5File::create(dir / "groups.h5");
  f.write("/time_history/sun_planet/0/deflection", std::vector<double>{1, 2});
  f.write("/time_history/sun_planet/1/deflection", std::vector<double>{3, 4});
  f.create_group("/time_history/sun_planet");  // existing: no-op
  EXPECT_TRUE(f.is_group("/time_history/sun_planet"));
  EXPECT_TRUE(f.exists("time_history/sun_planet/0/deflection"));  // relative = from root
  EXPECT_FALSE(f.is_group("/time_history/sun_planet/0/deflection"));
  EXPECT_FALSE(f.exists("/time_history/planet_ring/0/deflection"));
  EXPECT_EQ(f.members("/time_history/sun_planet"), (std::vector<std::string>{"0", "1"}));
}

TEST(H5File, LargeDatasetsAreCompressedAndReadBackExactly) {
  test::TempDir dir;
  const std::size_t n = 200000;
  std::vector<double> ramp(n);
  std::iota(ramp.begin(), ramp.end(), 0.0);
  DatasetOptions options;
  options.compress = true;
  {
    auto compressed = H5File::create(dir / "compressed.h5");
    compressed.write("/x", ramp, options);
    compressed.close();
    auto plain = H5File::create(dir / "plain.h5");
    plain.write("/x", ramp);
    plain.close();
  }
  EXPECT_EQ(H5File::open(dir / "compressed.h5").read_doubles("/x"), ramp);
  const auto compressed_size = std::filesystem::file_size(dir / "compressed.h5");
  const auto plain_size = std::filesystem::file_size(dir / "plain.h5");
  EXPECT_LT(compressed_size, plain_size / 2) << "deflate not applied";
}

TEST(H5File, NDimensionalDatasetsKeepTheirShapeAndCOrder) {
  test::TempDir dir;
  const auto path = dir / "nd.h5";
  // value = 100 i + 10 j + k at [i][j][k]: C order puts k fastest.
  const std::array<std::size_t, 3> dims{2, 3, 4};
  std::vector<double> cube;
  for (std::size_t i = 0; i < dims[0]; ++i)
    for (std::size_t j = 0; j < dims[1]; ++j)
      for (std::size_t k = 0; k < dims[2]; ++k) cube.push_back(static_cast<double>(100 * i + 10 * j + k));
  {
    auto f = H5File::create(path);
    f.write_nd("/cube", cube, dims);
    f.write_nd("/rank4", std::vector<double>(2 * 1 * 3 * 2, 0.5), std::array<std::size_t, 4>{2, 1, 3, 2});
    f.write_nd("/scalar", std::vector<double>{7.25}, std::span<const std::size_t>{});
    f.write_nd("/empty", std::vector<double>{}, std::array<std::size_t, 3>{0, 3, 4});
    f.close();
  }
  const auto f = H5File::open(path);
  EXPECT_EQ(f.shape("/cube"), (std::vector<std::size_t>{2, 3, 4}));
  const auto back = f.read_doubles("/cube");
  EXPECT_EQ(back, cube);
  EXPECT_EQ(back.at(1 * 12 + 2 * 4 + 3), 123.0) << "[1][2][3] not at its row-major position";
  EXPECT_EQ(f.shape("/rank4"), (std::vector<std::size_t>{2, 1, 3, 2}));
  EXPECT_TRUE(f.shape("/scalar").empty());
  EXPECT_EQ(f.read_scalar("/scalar"), 7.25);
  EXPECT_EQ(f.shape("/empty"), (std::vector<std::size_t>{0, 3, 4}));
  EXPECT_TRUE(f.read_doubles("/empty").empty());
}

TEST(H5File, LargeNDimensionalDatasetsAreCompressedAndReadBackExactly) {
  test::TempDir dir;
  DatasetOptions options;
  options.compress = true;
  // (updates, teeth, elements) as for wear depths, and a row longer than one chunk.
  const std::array<std::size_t, 3> depth_dims{40, 81, 64};
  std::vector<double> depth(40 * 81 * 64);
  for (std::size_t n = 0; n < depth.size(); ++n) depth[n] = 1e-6 * static_cast<double>((n % 64) * (n / (81 * 64)));
  const std::array<std::size_t, 2> wide_dims{3, 50000};
  std::vector<double> wide(3 * 50000);
  std::iota(wide.begin(), wide.end(), 0.0);
  {
    auto compressed = H5File::create(dir / "compressed.h5");
    compressed.write_nd("/depth", depth, depth_dims, options);
    compressed.write_nd("/wide", wide, wide_dims, options);
    compressed.close();
    auto plain = H5File::create(dir / "plain.h5");
    plain.write_nd("/depth", depth, depth_dims);
    plain.write_nd("/wide", wide, wide_dims);
    plain.close();
  }
  const auto f = H5File::open(dir / "compressed.h5");
  EXPECT_EQ(f.shape("/depth"), (std::vector<std::size_t>{40, 81, 64}));
  EXPECT_EQ(f.read_doubles("/depth"), depth);
  EXPECT_EQ(f.shape("/wide"), (std::vector<std::size_t>{3, 50000}));
  EXPECT_EQ(f.read_doubles("/wide"), wide);
  EXPECT_LT(std::filesystem::file_size(dir / "compressed.h5"), std::filesystem::file_size(dir / "plain.h5") / 2)
      << "deflate not applied";
}

TEST(H5File, NDimensionalWriteRejectsAShapeTheValuesDoNotFill) {
  test::TempDir dir;
  auto f = H5File::create(dir / "nd-errors.h5");
  auto e = thrown<IoError>([&] { f.write_nd("/cube", std::vector<double>(23), std::array<std::size_t, 3>{2, 3, 4}); });
  ASSERT_TRUE(e) << "23 values written as 2 x 3 x 4";
  EXPECT_TRUE(contains(e->what(), "'/cube'"));
  EXPECT_TRUE(contains(e->what(), "23 values do not fill 2 x 3 x 4"));
  e = thrown<IoError>([&] { f.write_nd("/s", std::vector<double>{}, std::span<const std::size_t>{}); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "scalar"));
  // A product that wraps around to the number of values given.
  const std::size_t half = std::size_t{1} << (sizeof(std::size_t) * 4);
  e = thrown<IoError>([&] { f.write_nd("/wrap", std::vector<double>{}, std::array<std::size_t, 2>{half, half}); });
  ASSERT_TRUE(e) << "overflowing shape accepted";
  EXPECT_FALSE(f.exists("/cube") || f.exists("/s") || f.exists("/wrap")) << "dataset created despite the error";
}

TEST(H5File, ErrorsNameTheFileAndTheObject) {
  test::TempDir dir;
  const auto path = dir / "errors.h5";
  auto f = H5File::create(path);
  f.write("/x", std::vector<double>{1.0});

  auto e = thrown<IoError>([&] { f.write("/x", std::vector<double>{2.0}); });
  ASSERT_TRUE(e) << "dataset silently overwritten";
  EXPECT_TRUE(contains(e->what(), path.string()));
  EXPECT_TRUE(contains(e->what(), "'/x'"));

  e = thrown<IoError>([&] { (void)f.read_doubles("/missing/y"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "'/missing/y'"));

  e = thrown<IoError>([&] { f.write("/x/child", std::vector<double>{1.0}); });
  ASSERT_TRUE(e) << "dataset used as a group";
  EXPECT_TRUE(contains(e->what(), "'/x/child'"));

  e = thrown<IoError>([&] { f.set_attribute("/nope", "unit", "m"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "'/nope'"));

  e = thrown<IoError>([&] { f.write_2d("/m", std::vector<double>{1, 2, 3}, 2, 2); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "2 x 2"));

  f.close();
  e = thrown<IoError>([&] { f.write("/y", std::vector<double>{1.0}); });
  ASSERT_TRUE(e) << "write to a closed file";
  EXPECT_TRUE(contains(e->what(), "closed"));

  e = thrown<IoError>([&] { (void)H5File::open(dir / "absent.h5"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "absent.h5"));

  e = thrown<IoError>([&] { (void)H5File::create(path, /*overwrite=*/false); });
  ASSERT_TRUE(e) << "existing file truncated although overwrite = false";
  EXPECT_TRUE(contains(e->what(), path.string()));

  test::write_text(dir / "not_hdf5.h5", "plain text");
  e = thrown<IoError>([&] { (void)H5File::open(dir / "not_hdf5.h5"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "not_hdf5.h5"));
}

TEST(H5File, UnitsAreWrittenUnderBothNames) {
  test::TempDir dir;
  auto f = H5File::create(dir / "units.h5");
  f.write("/v", std::vector<double>{1.0});
  f.set_units("/v", "m/s^2");
  EXPECT_EQ(f.read_string_attribute("/v", "unit"), "m/s^2");
  EXPECT_EQ(f.read_string_attribute("/v", "units"), "m/s^2");
}

TEST(H5File, DimensionScalesAreAttachedAndLabelled) {
  test::TempDir dir;
  const auto path = dir / "scales.h5";
  {
    auto f = H5File::create(path);
    f.write("/g/time", std::vector<double>{0.0, 0.5, 1.0});
    f.write("/g/sub/signal", std::vector<double>{1, 2, 3});
    f.write_2d("/g/matrix", std::vector<double>{1, 2, 3, 4, 5, 6}, 3, 2);
    f.make_dimension_scale("/g/time", "time");
    f.attach_dimension_scale("/g/sub/signal", "/g/time", 0);
    f.attach_dimension_scale("/g/matrix", "/g/time", 0);
    f.set_dimension_label("/g/matrix", 1, "column");
    f.close();
  }
  const auto f = H5File::open(path);
  EXPECT_TRUE(f.is_dimension_scale("/g/time"));
  EXPECT_FALSE(f.is_dimension_scale("/g/sub/signal"));
  EXPECT_EQ(f.dimension_scales("/g/sub/signal", 0), (std::vector<std::string>{"/g/time"}));
  EXPECT_EQ(f.dimension_scales("/g/matrix", 0), (std::vector<std::string>{"/g/time"}));
  EXPECT_TRUE(f.dimension_scales("/g/matrix", 1).empty());
  EXPECT_EQ(f.dimension_label("/g/matrix", 1), "column");
  EXPECT_EQ(f.dimension_label("/g/sub/signal", 0), "");
  EXPECT_EQ(f.read_doubles("/g/sub/signal"), (std::vector<double>{1, 2, 3})) << "attaching changed the data";
}

TEST(H5File, DimensionScaleErrorsNameTheObject) {
  test::TempDir dir;
  auto f = H5File::create(dir / "scale_errors.h5");
  f.write("/time", std::vector<double>{0.0, 1.0});
  f.write("/short", std::vector<double>{1.0});
  f.write_2d("/matrix", std::vector<double>{1, 2, 3, 4}, 2, 2);
  f.make_dimension_scale("/time", "time");

  auto e = thrown<IoError>([&] { f.attach_dimension_scale("/short", "/time", 0); });
  ASSERT_TRUE(e) << "a scale of another length was attached";
  EXPECT_TRUE(contains(e->what(), "'/short'"));
  EXPECT_TRUE(contains(e->what(), "length"));

  e = thrown<IoError>([&] { f.attach_dimension_scale("/matrix", "/time", 2); });
  ASSERT_TRUE(e) << "attached to a dimension the dataset does not have";

  e = thrown<IoError>([&] { f.make_dimension_scale("/matrix", "m"); });
  ASSERT_TRUE(e) << "a 2-D dimension scale";
  EXPECT_TRUE(contains(e->what(), "1-D"));

  e = thrown<IoError>([&] { f.set_dimension_label("/missing", 0, "x"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "'/missing'"));
}

TEST(H5File, MovedFromFileIsClosedAndTheTargetUsable) {
  test::TempDir dir;
  auto a = H5File::create(dir / "move.h5");
  H5File b = std::move(a);
  EXPECT_FALSE(a.is_open());  // NOLINT(bugprone-use-after-move): documented state
  b.write("/x", std::vector<double>{1.0});
  b.close();
  EXPECT_EQ(H5File::open(dir / "move.h5").read_doubles("/x"), std::vector<double>{1.0});
}

} // namespace
} // namespace pw::io
