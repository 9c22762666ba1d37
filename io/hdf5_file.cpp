#include "io/hdf5_file.hpp"

#include "io/io_error.hpp"

#include <hdf5.h>
#include <hdf5_hl.h>

#include <algorithm>
#include <limits>
#include <sstream>
#include <type_traits>
#include <utility>

namespace pw::io {
namespace {

static_assert(std::is_same_v<hid_t, std::int64_t>, "hid_t is 64-bit from HDF5 1.10 on");
static_assert(sizeof(hsize_t) == sizeof(unsigned long long));

/// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer closer) noexcept : id_(id), closer_(closer) {}
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, -1)), closer_(other.closer_) {}
  Handle& operator=(Handle&&) = delete;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }
  hid_t get() const noexcept { return id_; }
  bool valid() const noexcept { return id_ >= 0; }

private:
  hid_t id_;
  Closer closer_;
};

/// Turns off HDF5's printing of its error stack to stderr; errors become
/// IoError messages instead (fail()).
void silence_hdf5_errors() {
  static const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
}

/// The current HDF5 error stack, cleared afterwards, as one line: the
/// outermost entry (what failed) and the innermost (why), e.g.
/// "H5Fopen: unable to open file ... H5F__super_read: file signature not found".
std::string error_stack() {
  std::vector<std::string> entries;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned /*n*/, const H5E_error2_t* e, void* data) -> herr_t {
        std::string entry = std::string(e->func_name ? e->func_name : "?") + ": " + (e->desc ? e->desc : "");
        std::replace(entry.begin(), entry.end(), '\n', ' ');
        static_cast<std::vector<std::string>*>(data)->push_back(std::move(entry));
        return 0;
      },
      &entries);
  H5Eclear2(H5E_DEFAULT);
  if (entries.empty()) return "HDF5 reported no details";
  if (entries.size() == 1) return entries.front();
  return entries.front() + " ... " + entries.back();
}

std::string absolute(std::string_view object_path) {
  std::string path;
  path.reserve(object_path.size() + 1);
  if (object_path.empty() || object_path.front() != '/') path.push_back('/');
  path.append(object_path);
  return path;
}

/// Variable-length UTF-8 string type.
Handle string_type() {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  return type;
}

/// Link creation properties: create missing parent groups.
Handle link_properties() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  H5Pset_char_encoding(lcpl.get(), H5T_CSET_UTF8);
  return lcpl;
}

/// Reads a string from an attribute or dataset of fixed or variable length.
/// `read(memtype, buffer)` performs the H5Aread / H5Dread.
template <class Read>
bool read_string_value(hid_t file_type, Read read, std::string& out) {
  if (H5Tget_class(file_type) != H5T_STRING) return false;
  Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_cset(mem.get(), H5Tget_cset(file_type));
  if (H5Tis_variable_str(file_type) > 0) {
    H5Tset_size(mem.get(), H5T_VARIABLE);
    char* buffer = nullptr;
    if (read(mem.get(), &buffer) < 0) return false;
    out = buffer ? buffer : "";
    Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
    H5Dvlen_reclaim(mem.get(), scalar.get(), H5P_DEFAULT, &buffer);
    return true;
  }
  const std::size_t size = H5Tget_size(file_type);
  H5Tset_size(mem.get(), size);
  std::string buffer(size, '\0');
  if (read(mem.get(), buffer.data()) < 0) return false;
  out = buffer.substr(0, buffer.find('\0'));
  return true;
}

} // namespace

// ---------------------------------------------------------------------------

H5File H5File::create(const std::filesystem::path& path, bool overwrite) {
  silence_hdf5_errors();
  const hid_t id = H5Fcreate(path.c_str(), overwrite ? H5F_ACC_TRUNC : H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) throw IoError(path.string() + ": cannot create HDF5 file: " + error_stack());
  return H5File(path, id);
}

H5File H5File::open(const std::filesystem::path& path, bool writable) {
  silence_hdf5_errors();
  if (!std::filesystem::exists(path)) throw IoError(path.string() + ": cannot open HDF5 file: no such file");
  const hid_t id = H5Fopen(path.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw IoError(path.string() + ": cannot open HDF5 file: " + error_stack());
  return H5File(path, id);
}

H5File::H5File(H5File&& other) noexcept : path_(std::move(other.path_)), id_(std::exchange(other.id_, -1)) {}

H5File& H5File::operator=(H5File&& other) noexcept {
  if (this != &other) {
    if (id_ >= 0) H5Fclose(id_);
    path_ = std::move(other.path_);
    id_ = std::exchange(other.id_, -1);
  }
  return *this;
}

H5File::~H5File() {
  if (id_ >= 0) H5Fclose(id_);
}

void H5File::close() {
  if (id_ < 0) return;
  const herr_t status = H5Fclose(std::exchange(id_, -1));
  if (status < 0) throw IoError(path_.string() + ": cannot close HDF5 file: " + error_stack());
}

void H5File::flush() {
  if (id_ < 0 || H5Fflush(id_, H5F_SCOPE_GLOBAL) < 0) fail("/", "flush");
}

void H5File::fail(std::string_view object_path, std::string_view action, std::string_view reason) const {
  const std::string details = !reason.empty() ? std::string(reason)
                              : id_ < 0       ? std::string("the file is closed")
                                              : error_stack();
  throw IoError(path_.string() + ": cannot " + std::string(action) + " '" + absolute(object_path) + "': " + details);
}

// --- writing ----------------------------------------------------------------

void H5File::check_new_object(const std::string& path, std::string_view action) const {
  if (id_ < 0) fail(path, action);
  if (exists(path)) fail(path, action, "an object of that name already exists");
  for (std::size_t slash = path.find('/', 1); slash != std::string::npos; slash = path.find('/', slash + 1)) {
    const std::string parent = path.substr(0, slash);
    if (exists(parent) && !is_group(parent)) fail(path, action, "'" + parent + "' is a dataset, not a group");
  }
}

void H5File::create_group(std::string_view group_path) {
  const std::string path = absolute(group_path);
  if (is_group(path)) return;
  check_new_object(path, "create group");
  const Handle lcpl = link_properties();
  const Handle group(H5Gcreate2(id_, path.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail(path, "create group");
}

void H5File::write_array(std::string_view dataset_path, const void* data, std::int64_t mem_type,
                         std::int64_t file_type, std::span<const std::size_t> dims, const DatasetOptions& options) {
  const std::string path = absolute(dataset_path);
  check_new_object(path, "create dataset");

  std::vector<hsize_t> h5dims(dims.begin(), dims.end());
  std::size_t count = 1;
  for (const std::size_t d : dims) count *= d;
  const Handle space(h5dims.empty() ? H5Screate(H5S_SCALAR)
                                    : H5Screate_simple(static_cast<int>(h5dims.size()), h5dims.data(), nullptr),
                     H5Sclose);
  const Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (!space.valid() || !dcpl.valid()) fail(path, "create dataspace of dataset");

  if (options.compress && !h5dims.empty() && count > 0 && count >= options.min_compressed_elements &&
      H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    // Chunks of about 128 KiB: whole trailing dimensions (rows, rows of
    // matrices, ...) as far as they fit, the innermost one split only if a
    // single row is larger than that.
    constexpr hsize_t target_elements = 16384;
    std::vector<hsize_t> chunk(h5dims.size());
    hsize_t remaining = target_elements;
    for (std::size_t i = chunk.size(); i-- > 0;) {
      chunk[i] = std::clamp<hsize_t>(remaining, 1, h5dims[i]);
      remaining = std::max<hsize_t>(remaining / chunk[i], 1);
    }
    if (H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()) < 0 || H5Pset_shuffle(dcpl.get()) < 0 ||
        H5Pset_deflate(dcpl.get(), static_cast<unsigned>(std::clamp(options.deflate_level, 1, 9))) < 0)
      fail(path, "set compression of dataset");
  }

  const Handle lcpl = link_properties();
  const Handle dataset(H5Dcreate2(id_, path.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
                       H5Dclose);
  if (!dataset.valid()) fail(path, "create dataset");
  if (count > 0 && H5Dwrite(dataset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail(path, "write dataset");
}

void H5File::write(std::string_view dataset_path, std::span<const double> values, const DatasetOptions& options) {
  const std::size_t dims[] = {values.size()};
  write_array(dataset_path, values.data(), H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, dims, options);
}

void H5File::write_2d(std::string_view dataset_path, std::span<const double> row_major, std::size_t rows,
                      std::size_t cols, const DatasetOptions& options) {
  const std::size_t dims[] = {rows, cols};
  write_nd(dataset_path, row_major, dims, options);
}

void H5File::write_nd(std::string_view dataset_path, std::span<const double> row_major,
                      std::span<const std::size_t> dims, const DatasetOptions& options) {
  // The element count, refusing a product that overflows (it could wrap to row_major.size()).
  std::size_t count = 1;
  bool overflow = false;
  for (const std::size_t d : dims) {
    if (d != 0 && count > std::numeric_limits<std::size_t>::max() / d) overflow = true;
    count *= d;
  }
  if (overflow || row_major.size() != count) {
    std::ostringstream msg;
    msg << path_.string() << ": cannot write dataset '" << absolute(dataset_path) << "': " << row_major.size()
        << " values do not fill ";
    if (dims.empty()) msg << "a scalar (1 value)";
    for (std::size_t i = 0; i < dims.size(); ++i) msg << (i ? " x " : "") << dims[i];
    throw IoError(msg.str());
  }
  write_array(dataset_path, row_major.data(), H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, dims, options);
}

void H5File::write(std::string_view dataset_path, std::span<const int> values, const DatasetOptions& options) {
  static_assert(sizeof(int) == 4);
  const std::size_t dims[] = {values.size()};
  write_array(dataset_path, values.data(), H5T_NATIVE_INT, H5T_STD_I32LE, dims, options);
}

void H5File::write_scalar(std::string_view dataset_path, double value) {
  write_array(dataset_path, &value, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, {}, {});
}

void H5File::write_string(std::string_view dataset_path, std::string_view value) {
  const std::string path = absolute(dataset_path);
  check_new_object(path, "create dataset");
  const Handle type = string_type();
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle lcpl = link_properties();
  const Handle dataset(H5Dcreate2(id_, path.c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                       H5Dclose);
  if (!dataset.valid()) fail(path, "create string dataset");
  const std::string text(value);
  const char* pointer = text.c_str();
  if (H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &pointer) < 0)
    fail(path, "write string dataset");
}

void H5File::write_strings(std::string_view dataset_path, std::span<const std::string> values) {
  const std::string path = absolute(dataset_path);
  check_new_object(path, "create dataset");
  const Handle type = string_type();
  const hsize_t dims[1] = {values.size()};
  const Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  const Handle lcpl = link_properties();
  const Handle dataset(H5Dcreate2(id_, path.c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                       H5Dclose);
  if (!dataset.valid()) fail(path, "create string dataset");
  std::vector<const char*> pointers;
  pointers.reserve(values.size());
  for (const auto& v : values) pointers.push_back(v.c_str());
  if (!values.empty() && H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()) < 0)
    fail(path, "write string dataset");
}

std::vector<std::string> H5File::read_strings(std::string_view dataset_path) const {
  const std::string path = absolute(dataset_path);
  const Handle dataset(id_ < 0 ? -1 : H5Dopen2(id_, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) fail(path, "open dataset");
  const Handle space(H5Dget_space(dataset.get()), H5Sclose);
  const Handle file_type(H5Dget_type(dataset.get()), H5Tclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0 || H5Sget_simple_extent_ndims(space.get()) != 1 || H5Tget_class(file_type.get()) != H5T_STRING ||
      H5Tis_variable_str(file_type.get()) <= 0)
    fail(path, "read", "not a 1-d variable-length string dataset");
  std::vector<char*> buffer(static_cast<std::size_t>(n), nullptr);
  const Handle type = string_type();
  if (n > 0 && H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
    fail(path, "read string dataset");
  std::vector<std::string> out;
  out.reserve(buffer.size());
  for (char* p : buffer) out.emplace_back(p ? p : "");
  if (n > 0) H5Dvlen_reclaim(type.get(), space.get(), H5P_DEFAULT, buffer.data());
  return out;
}

namespace {
/// Creates (replacing) attribute `name` of type `type` on `object` and writes `data`.
herr_t write_attribute(hid_t object, const std::string& name, hid_t file_type, hid_t mem_type, const void* data) {
  if (H5Aexists(object, name.c_str()) > 0 && H5Adelete(object, name.c_str()) < 0) return -1;
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle attribute(H5Acreate2(object, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attribute.valid()) return -1;
  return H5Awrite(attribute.get(), mem_type, data);
}
} // namespace

void H5File::set_attribute(std::string_view object_path, std::string_view name, std::string_view value) {
  const std::string path = absolute(object_path);
  const Handle object(id_ < 0 ? -1 : H5Oopen(id_, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!object.valid()) fail(path, "open object to set attribute '" + std::string(name) + "' on");
  const Handle type = string_type();
  const std::string text(value);
  const char* pointer = text.c_str();
  if (write_attribute(object.get(), std::string(name), type.get(), type.get(), &pointer) < 0)
    fail(path, "write attribute '" + std::string(name) + "' of");
}

void H5File::set_attribute(std::string_view object_path, std::string_view name, double value) {
  const std::string path = absolute(object_path);
  const Handle object(id_ < 0 ? -1 : H5Oopen(id_, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!object.valid()) fail(path, "open object to set attribute '" + std::string(name) + "' on");
  if (write_attribute(object.get(), std::string(name), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value) < 0)
    fail(path, "write attribute '" + std::string(name) + "' of");
}

void H5File::set_attribute(std::string_view object_path, std::string_view name, std::int64_t value) {
  const std::string path = absolute(object_path);
  const Handle object(id_ < 0 ? -1 : H5Oopen(id_, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!object.valid()) fail(path, "open object to set attribute '" + std::string(name) + "' on");
  if (write_attribute(object.get(), std::string(name), H5T_STD_I64LE, H5T_NATIVE_INT64, &value) < 0)
    fail(path, "write attribute '" + std::string(name) + "' of");
}

void H5File::set_units(std::string_view object_path, std::string_view unit) {
  set_attribute(object_path, "unit", unit);
  set_attribute(object_path, "units", unit);
}

// --- dimension scales ---------------------------------------------------------

namespace {
/// Opens a dataset; an invalid handle if it is missing or `file` is closed.
Handle open_dataset(hid_t file, const std::string& path) {
  return Handle(file < 0 ? -1 : H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
}
} // namespace

void H5File::make_dimension_scale(std::string_view dataset_path, std::string_view name) {
  const std::string path = absolute(dataset_path);
  const Handle dataset = open_dataset(id_, path);
  if (!dataset.valid()) fail(path, "open dataset to make it a dimension scale");
  if (shape(path).size() != 1) fail(path, "make a dimension scale of", "a dimension scale must be 1-D");
  if (H5DSset_scale(dataset.get(), std::string(name).c_str()) < 0) fail(path, "make a dimension scale of");
}

void H5File::attach_dimension_scale(std::string_view dataset_path, std::string_view scale_path, unsigned dim) {
  const std::string path = absolute(dataset_path), scale = absolute(scale_path);
  const std::string action = "attach dimension scale '" + scale + "' to dimension " + std::to_string(dim) + " of";
  const Handle dataset = open_dataset(id_, path);
  const Handle scale_set = open_dataset(id_, scale);
  if (!dataset.valid() || !scale_set.valid()) fail(path, action);
  // H5DS does not check lengths; netCDF readers (xarray) reject a mismatch.
  const std::vector<std::size_t> dims = shape(path), scale_dims = shape(scale);
  if (dim >= dims.size() || scale_dims.size() != 1 || scale_dims[0] != dims[dim])
    fail(path, action, "the scale's length differs from the dimension's (or the dimension does not exist)");
  if (H5DSattach_scale(dataset.get(), scale_set.get(), dim) < 0) fail(path, action);
}

void H5File::set_dimension_label(std::string_view dataset_path, unsigned dim, std::string_view label) {
  const std::string path = absolute(dataset_path);
  const std::string action = "label dimension " + std::to_string(dim) + " of";
  const Handle dataset = open_dataset(id_, path);
  if (!dataset.valid()) fail(path, action);
  if (dim >= shape(path).size()) fail(path, action, "the dataset has no such dimension");
  if (H5DSset_label(dataset.get(), dim, std::string(label).c_str()) < 0) fail(path, action);
}

bool H5File::is_dimension_scale(std::string_view dataset_path) const {
  const Handle dataset = open_dataset(id_, absolute(dataset_path));
  if (!dataset.valid()) fail(dataset_path, "open dataset");
  return H5DSis_scale(dataset.get()) > 0;
}

std::vector<std::string> H5File::dimension_scales(std::string_view dataset_path, unsigned dim) const {
  const std::string path = absolute(dataset_path);
  const Handle dataset = open_dataset(id_, path);
  if (!dataset.valid()) fail(path, "open dataset");
  std::vector<std::string> out;
  if (H5DSget_num_scales(dataset.get(), dim) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    return out;
  }
  const auto collect = [](hid_t /*dataset*/, unsigned /*dim*/, hid_t scale, void* data) -> herr_t {
    const ssize_t size = H5Iget_name(scale, nullptr, 0);
    if (size < 0) return -1;
    std::string name(static_cast<std::size_t>(size) + 1, '\0');
    H5Iget_name(scale, name.data(), name.size());
    name.resize(static_cast<std::size_t>(size));
    static_cast<std::vector<std::string>*>(data)->push_back(std::move(name));
    return 0;
  };
  if (H5DSiterate_scales(dataset.get(), dim, nullptr, collect, &out) < 0) fail(path, "list the dimension scales of");
  return out;
}

std::string H5File::dimension_label(std::string_view dataset_path, unsigned dim) const {
  const std::string path = absolute(dataset_path);
  const Handle dataset = open_dataset(id_, path);
  if (!dataset.valid()) fail(path, "open dataset");
  const ssize_t size = H5DSget_label(dataset.get(), dim, nullptr, 0);
  if (size < 0) fail(path, "read the dimension label of");
  std::string label(static_cast<std::size_t>(size) + 1, '\0');
  H5DSget_label(dataset.get(), dim, label.data(), label.size());
  label.resize(static_cast<std::size_t>(size));
  return label;
}

// --- reading ----------------------------------------------------------------

bool H5File::exists(std::string_view object_path) const {
  if (id_ < 0) return false;
  const std::string path = absolute(object_path);
  // H5Lexists fails (rather than returning false) when a parent is missing:
  // check each prefix in turn.
  std::size_t pos = 1;
  while (pos <= path.size()) {
    const std::size_t slash = path.find('/', pos);
    const std::string prefix = path.substr(0, slash);
    if (prefix.size() > 1 && H5Lexists(id_, prefix.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    if (slash == std::string::npos) break;
    pos = slash + 1;
  }
  return true;
}

bool H5File::is_group(std::string_view object_path) const {
  if (!exists(object_path)) return false;
  const Handle object(H5Oopen(id_, absolute(object_path).c_str(), H5P_DEFAULT), H5Oclose);
  return object.valid() && H5Iget_type(object.get()) == H5I_GROUP;
}

std::vector<std::string> H5File::members(std::string_view group_path) const {
  const std::string path = absolute(group_path);
  const Handle group(id_ < 0 ? -1 : H5Gopen2(id_, path.c_str(), H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail(path, "open group");
  H5G_info_t info{};
  if (H5Gget_info(group.get(), &info) < 0) fail(path, "list group");
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t size = H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (size < 0) fail(path, "list group");
    std::string name(static_cast<std::size_t>(size) + 1, '\0');
    H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(size));
    names.push_back(std::move(name));
  }
  return names;
}

std::vector<std::size_t> H5File::shape(std::string_view dataset_path) const {
  const std::string path = absolute(dataset_path);
  const Handle dataset(id_ < 0 ? -1 : H5Dopen2(id_, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) fail(path, "open dataset");
  const Handle space(H5Dget_space(dataset.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) fail(path, "read the shape of dataset");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return {dims.begin(), dims.end()};
}

namespace {
template <class T>
bool read_all(hid_t file, const std::string& path, hid_t mem_type, std::vector<T>& out) {
  const Handle dataset(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) return false;
  const Handle space(H5Dget_space(dataset.get()), H5Sclose);
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  if (count < 0) return false;
  out.assign(static_cast<std::size_t>(count), T{});
  return count == 0 || H5Dread(dataset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) >= 0;
}
} // namespace

std::vector<double> H5File::read_doubles(std::string_view dataset_path) const {
  const std::string path = absolute(dataset_path);
  std::vector<double> out;
  if (id_ < 0 || !read_all(id_, path, H5T_NATIVE_DOUBLE, out)) fail(path, "read dataset");
  return out;
}

std::vector<int> H5File::read_ints(std::string_view dataset_path) const {
  const std::string path = absolute(dataset_path);
  std::vector<int> out;
  if (id_ < 0 || !read_all(id_, path, H5T_NATIVE_INT, out)) fail(path, "read dataset");
  return out;
}

double H5File::read_scalar(std::string_view dataset_path) const {
  const std::vector<double> values = read_doubles(dataset_path);
  if (values.size() != 1) {
    std::ostringstream msg;
    msg << path_.string() << ": dataset '" << absolute(dataset_path) << "' holds " << values.size()
        << " values, expected 1";
    throw IoError(msg.str());
  }
  return values.front();
}

std::string H5File::read_string(std::string_view dataset_path) const {
  const std::string path = absolute(dataset_path);
  const Handle dataset(id_ < 0 ? -1 : H5Dopen2(id_, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) fail(path, "open dataset");
  const Handle type(H5Dget_type(dataset.get()), H5Tclose);
  std::string out;
  const auto read = [&](hid_t mem, void* buffer) {
    return H5Dread(dataset.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
  };
  if (!read_string_value(type.get(), read, out)) fail(path, "read string dataset");
  return out;
}

bool H5File::has_attribute(std::string_view object_path, std::string_view name) const {
  if (!exists(object_path)) return false;
  const Handle object(H5Oopen(id_, absolute(object_path).c_str(), H5P_DEFAULT), H5Oclose);
  return object.valid() && H5Aexists(object.get(), std::string(name).c_str()) > 0;
}

std::string H5File::read_string_attribute(std::string_view object_path, std::string_view name) const {
  const std::string path = absolute(object_path);
  const std::string what = "read string attribute '" + std::string(name) + "' of";
  const Handle attribute(id_ < 0 ? -1 : H5Aopen_by_name(id_, path.c_str(), std::string(name).c_str(), H5P_DEFAULT,
                                                        H5P_DEFAULT),
                         H5Aclose);
  if (!attribute.valid()) fail(path, what);
  const Handle type(H5Aget_type(attribute.get()), H5Tclose);
  std::string out;
  const auto read = [&](hid_t mem, void* buffer) { return H5Aread(attribute.get(), mem, buffer); };
  if (!read_string_value(type.get(), read, out)) fail(path, what);
  return out;
}

double H5File::read_double_attribute(std::string_view object_path, std::string_view name) const {
  const std::string path = absolute(object_path);
  const Handle attribute(id_ < 0 ? -1 : H5Aopen_by_name(id_, path.c_str(), std::string(name).c_str(), H5P_DEFAULT,
                                                        H5P_DEFAULT),
                         H5Aclose);
  double value = 0;
  if (!attribute.valid() || H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value) < 0)
    fail(path, "read attribute '" + std::string(name) + "' of");
  return value;
}

std::int64_t H5File::read_int_attribute(std::string_view object_path, std::string_view name) const {
  const std::string path = absolute(object_path);
  const Handle attribute(id_ < 0 ? -1 : H5Aopen_by_name(id_, path.c_str(), std::string(name).c_str(), H5P_DEFAULT,
                                                        H5P_DEFAULT),
                         H5Aclose);
  std::int64_t value = 0;
  if (!attribute.valid() || H5Aread(attribute.get(), H5T_NATIVE_INT64, &value) < 0)
    fail(path, "read attribute '" + std::string(name) + "' of");
  return value;
}

} // namespace pw::io
