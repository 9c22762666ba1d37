// A thin RAII wrapper over the HDF5 C API (serial HDF5 >= 1.10): create or
// open a file, write datasets and attributes by '/'-separated path (groups are
// created on demand), read them back.
//
// Conventions:
//  * Doubles are stored as IEEE little-endian 64-bit, ints as 32-bit; 2-D and
//    N-D arrays are row-major (C order), as numpy/h5py expect.
//  * Strings (datasets and attributes) are variable-length UTF-8 scalars, so
//    h5py returns attributes as `str` and datasets via `.asstr()[()]`.
//  * Every failure throws pw::io::IoError naming the file and object path,
//    followed by the HDF5 error stack; HDF5's automatic printing of errors to
//    stderr is switched off when the first H5File is created.
//  * Not thread-safe (serial HDF5): one thread per H5File at a time.
//
// Example:
//   auto f = pw::io::H5File::create("out.h5");
//   f.write("/time_history/time", time_s);
//   f.set_attribute("/time_history/time", "unit", "s");
//   f.close();  // reports errors; the destructor closes silently
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pw::io {

/// Storage options of a dataset.
struct DatasetOptions {
  /// Chunked storage with shuffle + deflate, if the dataset has at least
  /// `min_compressed_elements` elements (small datasets stay contiguous).
  bool compress = false;
  int deflate_level = 4;  ///< 1 (fast) .. 9 (small)
  std::size_t min_compressed_elements = 4096;
};

class H5File {
public:
  /// Creates (truncating an existing file if `overwrite`, else failing).
  static H5File create(const std::filesystem::path& path, bool overwrite = true);
  /// Opens an existing file read-only, or read-write if `writable`.
  static H5File open(const std::filesystem::path& path, bool writable = false);

  H5File(H5File&& other) noexcept;
  H5File& operator=(H5File&& other) noexcept;
  H5File(const H5File&) = delete;
  H5File& operator=(const H5File&) = delete;
  ~H5File();  ///< closes without throwing; call close() to see errors

  /// Flushes and closes; further calls are errors. Idempotent.
  void close();
  bool is_open() const noexcept { return id_ >= 0; }
  const std::filesystem::path& path() const noexcept { return path_; }

  // --- writing ----------------------------------------------------------
  /// Creates the group (and its parents) if missing.
  void create_group(std::string_view group_path);
  /// 1-D dataset of doubles.
  void write(std::string_view dataset_path, std::span<const double> values, const DatasetOptions& options = {});
  /// 2-D dataset, `row_major` holds rows * cols values.
  void write_2d(std::string_view dataset_path, std::span<const double> row_major, std::size_t rows,
                std::size_t cols, const DatasetOptions& options = {});
  /// Dataset of any rank: `dims` = {d0, d1, ...} (empty = 0-d scalar) and
  /// `row_major` holds d0 * d1 * ... values, the last index varying fastest
  /// (numpy's C order). Compressed chunks (about 128 KiB) span whole trailing
  /// dimensions where these fit.
  /// Example: write_nd("/wear/sun/depth", depth, std::array<std::size_t, 3>{updates, teeth, elements}).
  void write_nd(std::string_view dataset_path, std::span<const double> row_major, std::span<const std::size_t> dims,
                const DatasetOptions& options = {});
  /// 1-D dataset of 32-bit ints.
  void write(std::string_view dataset_path, std::span<const int> values, const DatasetOptions& options = {});
  /// 0-d (scalar) double dataset: h5py's f[path][()] is a float.
  void write_scalar(std::string_view dataset_path, double value);
  /// 0-d variable-length UTF-8 string dataset.
  void write_string(std::string_view dataset_path, std::string_view value);
  /// 1-d variable-length UTF-8 string dataset (what h5py writes for a list of
  /// str; `.asstr()[:]` reads it back).
  void write_strings(std::string_view dataset_path, std::span<const std::string> values);

  /// Attribute on a group or dataset ("/" = the file's root group); an
  /// existing attribute of the same name is replaced.
  void set_attribute(std::string_view object_path, std::string_view name, std::string_view value);
  void set_attribute(std::string_view object_path, std::string_view name, const char* value) {
    set_attribute(object_path, name, std::string_view(value));
  }
  void set_attribute(std::string_view object_path, std::string_view name, double value);
  void set_attribute(std::string_view object_path, std::string_view name, std::int64_t value);
  /// The unit of a dataset (or group) as two equal string attributes: `unit`,
  /// which this project's readers use, and `units`, the CF / netCDF name that
  /// xarray, netCDF tools and pint-based readers look for.
  void set_units(std::string_view object_path, std::string_view unit);

  // --- dimension scales (HDF5 high-level H5DS API) ------------------------
  // A dimension scale is a 1-D dataset that labels one dimension of other
  // datasets (e.g. /time_history/time for every channel); h5py shows it as
  // dataset.dims[k][0], xarray (h5netcdf engine) as the coordinate of that
  // dimension.
  /// Makes a 1-D dataset a dimension scale called `name`.
  void make_dimension_scale(std::string_view dataset_path, std::string_view name);
  /// Attaches the dimension scale `scale_path` to dimension `dim` of a
  /// dataset; the scale's length must equal that dimension's.
  void attach_dimension_scale(std::string_view dataset_path, std::string_view scale_path, unsigned dim);
  /// Names dimension `dim` of a dataset (h5py: dataset.dims[dim].label), for
  /// dimensions that have no scale of their own, e.g. "tooth".
  void set_dimension_label(std::string_view dataset_path, unsigned dim, std::string_view label);

  void flush();

  // --- reading (tests, post-processing) -----------------------------------
  bool exists(std::string_view object_path) const;
  bool is_group(std::string_view object_path) const;
  /// Names of the direct members of a group, in name order.
  std::vector<std::string> members(std::string_view group_path) const;
  /// Dimensions of a dataset ({} for a scalar).
  std::vector<std::size_t> shape(std::string_view dataset_path) const;
  /// All values of a double dataset of any rank, row-major.
  std::vector<double> read_doubles(std::string_view dataset_path) const;
  std::vector<int> read_ints(std::string_view dataset_path) const;
  double read_scalar(std::string_view dataset_path) const;
  std::string read_string(std::string_view dataset_path) const;
  /// A 1-d variable-length string dataset written by write_strings (or h5py).
  std::vector<std::string> read_strings(std::string_view dataset_path) const;
  bool has_attribute(std::string_view object_path, std::string_view name) const;
  std::string read_string_attribute(std::string_view object_path, std::string_view name) const;
  double read_double_attribute(std::string_view object_path, std::string_view name) const;
  std::int64_t read_int_attribute(std::string_view object_path, std::string_view name) const;
  bool is_dimension_scale(std::string_view dataset_path) const;
  /// Paths of the dimension scales attached to dimension `dim` of a dataset.
  std::vector<std::string> dimension_scales(std::string_view dataset_path, unsigned dim) const;
  /// The label of dimension `dim` of a dataset ("" if none).
  std::string dimension_label(std::string_view dataset_path, unsigned dim) const;

private:
  H5File(std::filesystem::path path, std::int64_t id) : path_(std::move(path)), id_(id) {}
  void write_array(std::string_view dataset_path, const void* data, std::int64_t mem_type, std::int64_t file_type,
                   std::span<const std::size_t> dims, const DatasetOptions& options);
  /// Throws IoError "<file>: cannot <action> '<object>': <reason>", by
  /// default the HDF5 error stack.
  [[noreturn]] void fail(std::string_view object_path, std::string_view action, std::string_view reason = {}) const;
  /// Checks that `object_path` is free and its existing parents are groups.
  void check_new_object(const std::string& object_path, std::string_view action) const;

  std::filesystem::path path_;
  std::int64_t id_ = -1;  ///< hid_t
};

} // namespace pw::io
