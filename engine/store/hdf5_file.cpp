#include "engine/store/hdf5_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>

namespace ggk::engine {

// The header keeps hdf5.h out of its includers and stores the file id as int64.
static_assert(std::is_same_v<hid_t, std::int64_t>, "HDF5 >= 1.10 uses 64-bit hid_t");

namespace {

namespace fs = std::filesystem;

// Chunks of about this many bytes: large enough for gzip to work well, small
// enough that reading one value does not inflate megabytes.
constexpr std::size_t kTargetChunkBytes = 256 * 1024;

// ---------------------------------------------------------------- errors

// Debian builds HDF5 thread-safe, where the error stack and its automatic
// printing are per thread: switch printing off once in every thread that
// calls HDF5 through this file (take_hdf5_reason() reports instead).
void disable_automatic_error_printing() {
  thread_local bool disabled = false;
  if (!disabled) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    disabled = true;
  }
}

herr_t collect_error_description(unsigned /*depth*/, const H5E_error2_t* error, void* data) {
  auto& descriptions = *static_cast<std::vector<std::string>*>(data);
  if (error->desc != nullptr && error->desc[0] != '\0' &&
      (descriptions.empty() || descriptions.back() != error->desc)) {
    descriptions.emplace_back(error->desc);
  }
  return 0;
}

// HDF5's reason for the last failure, from its error stack (which is then
// cleared): the outermost description says what failed, the innermost why.
std::string take_hdf5_reason() {
  std::vector<std::string> descriptions;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect_error_description, &descriptions);
  H5Eclear2(H5E_DEFAULT);
  if (descriptions.empty()) return "HDF5 gave no reason";
  std::string reason = descriptions.front();
  if (descriptions.size() > 1) reason += ": " + descriptions.back();
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  return reason;
}

std::string in_quotes(std::string_view text) {
  // Appended piece by piece: GCC 12 at -O3 reports a false -Wrestrict on
  // "'" + std::string(...) (GCC bug 105329).
  std::string result;
  result.reserve(text.size() + 2);
  result += '\'';
  result += text;
  result += '\'';
  return result;
}

std::string file_prefix(const fs::path& file) {
  return "HDF5 file " + in_quotes(file.string());
}

// A failure of an HDF5 call: names the file, what was attempted, the object
// and HDF5's reason.
[[noreturn]] void throw_hdf5_error(const fs::path& file, std::string_view what,
                                   std::string_view object_path) {
  throw std::runtime_error(file_prefix(file) + ": cannot " + std::string(what) + " " +
                           in_quotes(object_path) + ": " + take_hdf5_reason());
}

// A misuse detected before calling HDF5 (wrong shape, existing path, ...).
[[noreturn]] void throw_store_error(const fs::path& file, std::string_view object_path,
                                    std::string_view problem) {
  throw std::runtime_error(file_prefix(file) + ": " + in_quotes(object_path) + ": " +
                           std::string(problem));
}

// ---------------------------------------------------------------- handles

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);

  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), closer_(other.closer_) {}
  Handle& operator=(Handle&&) = delete;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }

  hid_t get() const { return id_; }

 private:
  hid_t id_;
  Closer closer_;
};

// Where an operation happens, to name it in errors. Every operation makes one
// first, so making one also silences HDF5's printing on the calling thread.
struct Context {
  Context(hid_t file_id, const fs::path& path) : file(file_id), file_path(path) {
    disable_automatic_error_printing();
  }

  hid_t file;
  const fs::path& file_path;
};

Handle checked(hid_t id, Handle::Closer closer, const Context& where, std::string_view what,
               std::string_view object_path) {
  if (id < 0) throw_hdf5_error(where.file_path, what, object_path);
  return Handle(id, closer);
}

void check(herr_t status, const Context& where, std::string_view what,
           std::string_view object_path) {
  if (status < 0) throw_hdf5_error(where.file_path, what, object_path);
}

Handle make_property_list(hid_t property_class, const Context& where,
                          std::string_view object_path) {
  return checked(H5Pcreate(property_class), H5Pclose, where, "create property list for",
                 object_path);
}

// Link creation properties that create missing parent groups.
Handle intermediate_groups_lcpl(const Context& where, std::string_view object_path) {
  Handle lcpl = make_property_list(H5P_LINK_CREATE, where, object_path);
  check(H5Pset_create_intermediate_group(lcpl.get(), 1), where, "set up parents of", object_path);
  return lcpl;
}

Handle open_dataset(const Context& where, const std::string& path) {
  return checked(H5Dopen2(where.file, path.c_str(), H5P_DEFAULT), H5Dclose, where, "open dataset",
                 path);
}

Handle dataset_type(const Context& where, const Handle& dataset, const std::string& path) {
  return checked(H5Dget_type(dataset.get()), H5Tclose, where, "get the type of", path);
}

Handle dataset_space(const Context& where, const Handle& dataset, const std::string& path) {
  return checked(H5Dget_space(dataset.get()), H5Sclose, where, "get the shape of", path);
}

std::vector<hsize_t> space_dims(const Context& where, const Handle& space,
                                const std::string& path) {
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) throw_hdf5_error(where.file_path, "get the rank of", path);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0) {
    throw_hdf5_error(where.file_path, "get the shape of", path);
  }
  return dims;
}

std::size_t element_count(std::span<const hsize_t> dims) {
  std::size_t count = 1;
  for (const hsize_t dim : dims) count *= static_cast<std::size_t>(dim);
  return count;
}

// ---------------------------------------------------------------- paths

// "a/b" and "/a/b/" both become "/a/b"; "" is an error.
std::string normalized(std::string_view path, const fs::path& file) {
  if (path.empty()) throw_store_error(file, path, "empty object path");
  std::string result = path.front() == '/' ? std::string(path) : "/" + std::string(path);
  while (result.size() > 1 && result.back() == '/') result.pop_back();
  return result;
}

std::string join(const std::string& parent, std::string_view child) {
  return parent == "/" ? parent + std::string(child) : parent + "/" + std::string(child);
}

// The longest existing prefix of a path that is not a group ("" if none):
// nothing can exist or be created below it.
struct Lookup {
  bool found = false;
  std::string blocking_parent;
};

Lookup look_up(const Context& where, const std::string& path) {
  if (path == "/") return {true, ""};
  // H5Lexists only looks at the last component and fails when a parent is
  // missing, so walk the path one component at a time; every parent must be a
  // group.
  std::size_t end = 0;
  while (end != std::string::npos) {
    end = path.find('/', end + 1);
    const std::string prefix = path.substr(0, end);
    if (prefix.back() == '/') continue;  // "//" in the path
    const htri_t found = H5Lexists(where.file, prefix.c_str(), H5P_DEFAULT);
    if (found < 0) throw_hdf5_error(where.file_path, "look up", prefix);
    if (found == 0) return {false, ""};
    if (end != std::string::npos) {
      const Handle object = checked(H5Oopen(where.file, prefix.c_str(), H5P_DEFAULT), H5Oclose,
                                    where, "open", prefix);
      if (H5Iget_type(object.get()) != H5I_GROUP) return {false, prefix};
    }
  }
  return {true, ""};
}

bool object_exists(const Context& where, const std::string& path) {
  return look_up(where, path).found;
}

void require_existing(const Context& where, const std::string& path) {
  if (!object_exists(where, path)) throw_store_error(where.file_path, path, "no such object");
}

// ---------------------------------------------------------------- types

template <class T>
struct NumericType;

template <>
struct NumericType<double> {
  static hid_t file() { return H5T_IEEE_F64LE; }
  static hid_t memory() { return H5T_NATIVE_DOUBLE; }
  static constexpr H5T_class_t kClass = H5T_FLOAT;
  static constexpr H5T_sign_t kSign = H5T_SGN_ERROR;
  static constexpr const char* kName = "float64";
};
template <>
struct NumericType<float> {
  static hid_t file() { return H5T_IEEE_F32LE; }
  static hid_t memory() { return H5T_NATIVE_FLOAT; }
  static constexpr H5T_class_t kClass = H5T_FLOAT;
  static constexpr H5T_sign_t kSign = H5T_SGN_ERROR;
  static constexpr const char* kName = "float32";
};
template <>
struct NumericType<std::int32_t> {
  static hid_t file() { return H5T_STD_I32LE; }
  static hid_t memory() { return H5T_NATIVE_INT32; }
  static constexpr H5T_class_t kClass = H5T_INTEGER;
  static constexpr H5T_sign_t kSign = H5T_SGN_2;
  static constexpr const char* kName = "int32";
};
template <>
struct NumericType<std::int64_t> {
  static hid_t file() { return H5T_STD_I64LE; }
  static hid_t memory() { return H5T_NATIVE_INT64; }
  static constexpr H5T_class_t kClass = H5T_INTEGER;
  static constexpr H5T_sign_t kSign = H5T_SGN_2;
  static constexpr const char* kName = "int64";
};
template <>
struct NumericType<std::uint8_t> {
  static hid_t file() { return H5T_STD_U8LE; }
  static hid_t memory() { return H5T_NATIVE_UINT8; }
  static constexpr H5T_class_t kClass = H5T_INTEGER;
  static constexpr H5T_sign_t kSign = H5T_SGN_NONE;
  static constexpr const char* kName = "uint8";
};

std::string describe_type(hid_t type) {
  const H5T_class_t type_class = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  switch (type_class) {
    case H5T_INTEGER:
      return std::string(H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") +
             std::to_string(8 * size);
    case H5T_FLOAT:
      return "float" + std::to_string(8 * size);
    case H5T_STRING:
      return "string";
    case H5T_COMPOUND:
      return "compound";
    default:
      return "type class " + std::to_string(static_cast<int>(type_class));
  }
}

template <class T>
bool has_numeric_type(hid_t type) {
  if (H5Tget_class(type) != NumericType<T>::kClass || H5Tget_size(type) != sizeof(T)) return false;
  return NumericType<T>::kClass != H5T_INTEGER || H5Tget_sign(type) == NumericType<T>::kSign;
}

// Variable-length UTF-8 string type (as h5py writes str).
Handle variable_string_type(const Context& where, std::string_view object_path) {
  Handle type = checked(H5Tcopy(H5T_C_S1), H5Tclose, where, "make string type for", object_path);
  check(H5Tset_size(type.get(), H5T_VARIABLE), where, "make string type for", object_path);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "make string type for", object_path);
  return type;
}

// Fixed-length, NUL-padded UTF-8 string type of `size` bytes.
Handle fixed_string_type(const Context& where, std::size_t size, std::string_view object_path) {
  Handle type = checked(H5Tcopy(H5T_C_S1), H5Tclose, where, "make string type for", object_path);
  check(H5Tset_size(type.get(), size), where, "make string type for", object_path);
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), where, "make string type for", object_path);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "make string type for", object_path);
  return type;
}

// The text of one fixed-length string element of `size` bytes.
std::string decode_fixed_string(const char* bytes, std::size_t size, H5T_str_t padding) {
  std::size_t length = 0;
  while (length < size && bytes[length] != '\0') ++length;
  if (padding == H5T_STR_SPACEPAD) {
    while (length > 0 && bytes[length - 1] == ' ') --length;
  }
  return std::string(bytes, length);
}

void require_no_nul(const Context& where, std::string_view object_path, std::string_view text) {
  if (text.find('\0') != std::string_view::npos) {
    throw_store_error(where.file_path, object_path, "string contains a NUL character");
  }
}

// ---------------------------------------------------------------- datasets

// Chunk shape of about kTargetChunkBytes for a non-empty dataset; every chunk
// dimension is >= 1 and <= the dataset's (HDF5 requires both for fixed sizes).
std::vector<hsize_t> chunk_shape(std::span<const hsize_t> dims, std::size_t element_size) {
  std::vector<hsize_t> chunk(dims.size(), 1);
  std::size_t budget = std::max<std::size_t>(1, kTargetChunkBytes / element_size);
  for (std::size_t i = dims.size(); i-- > 0;) {  // innermost dimension first
    chunk[i] = std::max<hsize_t>(1, std::min<hsize_t>(dims[i], budget));
    budget = std::max<std::size_t>(1, budget / static_cast<std::size_t>(chunk[i]));
  }
  return chunk;
}

// Dataset creation properties: chunked, shuffle + gzip, unless the dataset is
// empty (contiguous: there is nothing to compress and no chunk would fit).
Handle compressed_dcpl(const Context& where, std::span<const hsize_t> dims,
                       std::size_t element_size, int gzip_level, std::string_view object_path) {
  Handle dcpl = make_property_list(H5P_DATASET_CREATE, where, object_path);
  if (element_count(dims) == 0) return dcpl;
  const std::vector<hsize_t> chunk = chunk_shape(dims, element_size);
  check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), where,
        "set chunks of", object_path);
  check(H5Pset_shuffle(dcpl.get()), where, "set shuffle filter of", object_path);
  if (gzip_level > 0) {
    check(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(gzip_level)), where,
          "set gzip filter of", object_path);
  }
  return dcpl;
}

// Creates a new dataset at path (parents included) and writes all of `data`.
void write_dataset(const Context& where, const std::string& path, std::span<const hsize_t> dims,
                   hid_t file_type, hid_t memory_type, std::size_t element_size, int gzip_level,
                   const void* data) {
  const Handle space =
      checked(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
              where, "create dataspace for", path);
  const Handle dcpl = compressed_dcpl(where, dims, element_size, gzip_level, path);
  const Handle lcpl = intermediate_groups_lcpl(where, path);
  const Handle dataset = checked(H5Dcreate2(where.file, path.c_str(), file_type, space.get(),
                                            lcpl.get(), dcpl.get(), H5P_DEFAULT),
                                 H5Dclose, where, "create dataset", path);
  if (element_count(dims) == 0) return;
  check(H5Dwrite(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), where,
        "write dataset", path);
}

// Reads a numeric dataset of exactly type T and the given rank.
template <class T>
std::vector<T> read_numeric(const Context& where, const std::string& path, std::size_t rank,
                            std::vector<hsize_t>& dims) {
  const Handle dataset = open_dataset(where, path);
  const Handle type = dataset_type(where, dataset, path);
  if (!has_numeric_type<T>(type.get())) {
    throw_store_error(where.file_path, path,
                      "holds " + describe_type(type.get()) + ", not " + NumericType<T>::kName);
  }
  const Handle space = dataset_space(where, dataset, path);
  dims = space_dims(where, space, path);
  if (dims.size() != rank) {
    throw_store_error(
        where.file_path, path,
        "has rank " + std::to_string(dims.size()) + ", expected " + std::to_string(rank));
  }
  std::vector<T> values(element_count(dims));
  if (!values.empty()) {
    check(H5Dread(dataset.get(), NumericType<T>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT,
                  values.data()),
          where, "read dataset", path);
  }
  return values;
}

template <class T>
void write_vector_of(const Context& where, const std::string& path, std::span<const T> values,
                     int gzip_level) {
  const hsize_t dims[1] = {values.size()};
  write_dataset(where, path, dims, NumericType<T>::file(), NumericType<T>::memory(), sizeof(T),
                gzip_level, values.data());
}

template <class T>
void write_matrix_of(const Context& where, const std::string& path, std::int64_t rows,
                     std::int64_t cols, std::span<const T> values, int gzip_level) {
  if (rows < 0 || cols < 0) throw_store_error(where.file_path, path, "negative matrix shape");
  const auto urows = static_cast<std::size_t>(rows);
  const auto ucols = static_cast<std::size_t>(cols);
  if (ucols != 0 && urows > std::numeric_limits<std::size_t>::max() / ucols) {
    throw_store_error(where.file_path, path, "matrix shape overflows");
  }
  if (values.size() != urows * ucols) {
    throw_store_error(where.file_path, path,
                      "matrix of " + std::to_string(rows) + " x " + std::to_string(cols) +
                          " given " + std::to_string(values.size()) + " values");
  }
  const hsize_t dims[2] = {urows, ucols};
  write_dataset(where, path, dims, NumericType<T>::file(), NumericType<T>::memory(), sizeof(T),
                gzip_level, values.data());
}

// ---------------------------------------------------------------- attributes

Handle open_attribute(const Context& where, const std::string& object_path,
                      const std::string& name) {
  require_existing(where, object_path);
  return checked(
      H5Aopen_by_name(where.file, object_path.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose, where, "open attribute " + in_quotes(name) + " of", object_path);
}

// Number of elements of an attribute (1 for a scalar).
std::size_t attribute_size(const Context& where, const Handle& attribute,
                           const std::string& object_path, const std::string& name) {
  const Handle space =
      checked(H5Aget_space(attribute.get()), H5Sclose, where,
              "get the shape of attribute " + in_quotes(name) + " of", object_path);
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  if (count < 0) {
    throw_hdf5_error(where.file_path, "get the size of attribute " + in_quotes(name) + " of",
                     object_path);
  }
  return static_cast<std::size_t>(count);
}

// Reads every element of a numeric attribute, converted to T within the same
// class (any integer to int64, any float to double).
template <class T>
std::vector<T> read_numeric_attribute(const Context& where, const std::string& object_path,
                                      const std::string& name) {
  const Handle attribute = open_attribute(where, object_path, name);
  const Handle type = checked(H5Aget_type(attribute.get()), H5Tclose, where,
                              "get the type of attribute " + in_quotes(name) + " of", object_path);
  if (H5Tget_class(type.get()) != NumericType<T>::kClass) {
    throw_store_error(where.file_path, object_path,
                      "attribute " + in_quotes(name) + " holds " + describe_type(type.get()) +
                          ", not " + NumericType<T>::kName);
  }
  std::vector<T> values(attribute_size(where, attribute, object_path, name));
  if (!values.empty()) {
    check(H5Aread(attribute.get(), NumericType<T>::memory(), values.data()), where,
          "read attribute " + in_quotes(name) + " of", object_path);
  }
  return values;
}

template <class T>
T read_scalar_attribute(const Context& where, const std::string& object_path,
                        const std::string& name) {
  const std::vector<T> values = read_numeric_attribute<T>(where, object_path, name);
  if (values.size() != 1) {
    throw_store_error(where.file_path, object_path,
                      "attribute " + in_quotes(name) + " has " + std::to_string(values.size()) +
                          " elements, expected 1");
  }
  return values.front();
}

// ---------------------------------------------------------------- CSR

void check_csr(const fs::path& file, const std::string& path, std::int64_t rows, std::int64_t cols,
               std::span<const std::int64_t> indptr, std::span<const std::int32_t> indices,
               std::size_t value_count) {
  const auto fail = [&](const std::string& problem) {
    throw_store_error(file, path, "invalid CSR matrix: " + problem);
  };
  if (rows < 0 || cols < 0) fail("negative shape");
  if (indptr.size() != static_cast<std::size_t>(rows) + 1) {
    fail("indptr has " + std::to_string(indptr.size()) + " entries for " + std::to_string(rows) +
         " rows");
  }
  if (indices.size() != value_count) {
    fail(std::to_string(indices.size()) + " indices but " + std::to_string(value_count) +
         " values");
  }
  if (indptr.front() != 0) fail("indptr[0] is not 0");
  for (std::size_t i = 1; i < indptr.size(); ++i) {
    if (indptr[i] < indptr[i - 1]) fail("indptr decreases at row " + std::to_string(i - 1));
  }
  if (static_cast<std::uint64_t>(indptr.back()) != indices.size()) {
    fail("indptr ends at " + std::to_string(indptr.back()) + " but there are " +
         std::to_string(indices.size()) + " entries");
  }
  for (const std::int32_t column : indices) {
    if (column < 0 || column >= cols) {
      fail("column index " + std::to_string(column) + " outside [0, " + std::to_string(cols) + ")");
    }
  }
}

// ---------------------------------------------------------------- tables

// ColumnType doubles as the index of the matching TableValue alternative.
static_assert(std::is_same_v<
              std::variant_alternative_t<static_cast<std::size_t>(ColumnType::kInt32), TableValue>,
              std::int32_t>);
static_assert(std::is_same_v<
              std::variant_alternative_t<static_cast<std::size_t>(ColumnType::kInt64), TableValue>,
              std::int64_t>);
static_assert(
    std::is_same_v<
        std::variant_alternative_t<static_cast<std::size_t>(ColumnType::kFloat64), TableValue>,
        double>);
static_assert(std::is_same_v<
              std::variant_alternative_t<static_cast<std::size_t>(ColumnType::kString), TableValue>,
              std::string>);

const char* column_type_name(ColumnType type) {
  switch (type) {
    case ColumnType::kInt32:
      return "int32";
    case ColumnType::kInt64:
      return "int64";
    case ColumnType::kFloat64:
      return "float64";
    case ColumnType::kString:
      return "string";
  }
  return "?";
}

std::size_t column_size(const TableColumn& column) {
  switch (column.type) {
    case ColumnType::kInt32:
      return sizeof(std::int32_t);
    case ColumnType::kInt64:
      return sizeof(std::int64_t);
    case ColumnType::kFloat64:
      return sizeof(double);
    case ColumnType::kString:
      return column.string_size;
  }
  return 0;
}

// Byte offset of every column in a packed row, and the row size (last entry).
std::vector<std::size_t> column_offsets(std::span<const TableColumn> columns) {
  std::vector<std::size_t> offsets{0};
  for (const auto& column : columns) offsets.push_back(offsets.back() + column_size(column));
  return offsets;
}

void check_columns(const Context& where, const std::string& path,
                   std::span<const TableColumn> columns) {
  if (columns.empty()) throw_store_error(where.file_path, path, "a table needs columns");
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const TableColumn& column = columns[i];
    if (column.name.empty() || column.name.find('\0') != std::string::npos) {
      throw_store_error(where.file_path, path,
                        "column " + std::to_string(i) + " has an invalid name");
    }
    if (column.type == ColumnType::kString && column.string_size == 0) {
      throw_store_error(where.file_path, path,
                        "string column " + in_quotes(column.name) + " has size 0");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (columns[j].name == column.name) {
        throw_store_error(where.file_path, path, "duplicate column " + in_quotes(column.name));
      }
    }
  }
}

// Packed compound type of the columns: in the file (little-endian standard
// types) or in memory (native types); both have the same offsets.
Handle row_type(const Context& where, const std::string& path, std::span<const TableColumn> columns,
                bool in_file) {
  const std::vector<std::size_t> offsets = column_offsets(columns);
  Handle compound =
      checked(H5Tcreate(H5T_COMPOUND, offsets.back()), H5Tclose, where, "make row type of", path);
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const TableColumn& column = columns[i];
    herr_t status = 0;
    switch (column.type) {
      case ColumnType::kInt32:
        status = H5Tinsert(compound.get(), column.name.c_str(), offsets[i],
                           in_file ? H5T_STD_I32LE : H5T_NATIVE_INT32);
        break;
      case ColumnType::kInt64:
        status = H5Tinsert(compound.get(), column.name.c_str(), offsets[i],
                           in_file ? H5T_STD_I64LE : H5T_NATIVE_INT64);
        break;
      case ColumnType::kFloat64:
        status = H5Tinsert(compound.get(), column.name.c_str(), offsets[i],
                           in_file ? H5T_IEEE_F64LE : H5T_NATIVE_DOUBLE);
        break;
      case ColumnType::kString: {
        const Handle string_type = fixed_string_type(where, column.string_size, path);
        status = H5Tinsert(compound.get(), column.name.c_str(), offsets[i], string_type.get());
        break;
      }
    }
    check(status, where, "add column " + in_quotes(column.name) + " to", path);
  }
  return compound;
}

std::vector<TableColumn> table_columns(const Context& where, const std::string& path,
                                       const Handle& dataset) {
  const Handle type = dataset_type(where, dataset, path);
  if (H5Tget_class(type.get()) != H5T_COMPOUND) {
    throw_store_error(where.file_path, path,
                      "holds " + describe_type(type.get()) + ", not a table (compound)");
  }
  const int count = H5Tget_nmembers(type.get());
  if (count < 0) throw_hdf5_error(where.file_path, "get the columns of", path);
  std::vector<TableColumn> columns;
  for (int i = 0; i < count; ++i) {
    const auto index = static_cast<unsigned>(i);
    char* raw_name = H5Tget_member_name(type.get(), index);
    if (raw_name == nullptr) throw_hdf5_error(where.file_path, "get the columns of", path);
    TableColumn column;
    column.name = raw_name;
    H5free_memory(raw_name);
    const Handle member =
        checked(H5Tget_member_type(type.get(), index), H5Tclose, where, "get the columns of", path);
    if (has_numeric_type<std::int32_t>(member.get())) {
      column.type = ColumnType::kInt32;
    } else if (has_numeric_type<std::int64_t>(member.get())) {
      column.type = ColumnType::kInt64;
    } else if (has_numeric_type<double>(member.get())) {
      column.type = ColumnType::kFloat64;
    } else if (H5Tget_class(member.get()) == H5T_STRING && H5Tis_variable_str(member.get()) == 0) {
      column.type = ColumnType::kString;
      column.string_size = H5Tget_size(member.get());
    } else {
      throw_store_error(where.file_path, path,
                        "column " + in_quotes(column.name) + " has unsupported type " +
                            describe_type(member.get()));
    }
    columns.push_back(std::move(column));
  }
  return columns;
}

// Packs rows into the native packed layout of columns, checking each value.
std::vector<unsigned char> pack_rows(const Context& where, const std::string& path,
                                     std::span<const TableColumn> columns,
                                     std::span<const TableRow> rows) {
  const std::vector<std::size_t> offsets = column_offsets(columns);
  const std::size_t row_size = offsets.back();
  std::vector<unsigned char> buffer(rows.size() * row_size, 0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const TableRow& row = rows[r];
    if (row.size() != columns.size()) {
      throw_store_error(where.file_path, path,
                        "row " + std::to_string(r) + " has " + std::to_string(row.size()) +
                            " values for " + std::to_string(columns.size()) + " columns");
    }
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const TableColumn& column = columns[c];
      unsigned char* cell = buffer.data() + r * row_size + offsets[c];
      const auto wrong = [&](const std::string& problem) {
        throw_store_error(
            where.file_path, path,
            "row " + std::to_string(r) + ", column " + in_quotes(column.name) + ": " + problem);
      };
      if (row[c].index() != static_cast<std::size_t>(column.type)) {
        wrong(std::string("expected a value of type ") + column_type_name(column.type));
      }
      switch (column.type) {
        case ColumnType::kInt32:
          std::memcpy(cell, &std::get<std::int32_t>(row[c]), sizeof(std::int32_t));
          break;
        case ColumnType::kInt64:
          std::memcpy(cell, &std::get<std::int64_t>(row[c]), sizeof(std::int64_t));
          break;
        case ColumnType::kFloat64:
          std::memcpy(cell, &std::get<double>(row[c]), sizeof(double));
          break;
        case ColumnType::kString: {
          const std::string& text = std::get<std::string>(row[c]);
          if (text.size() > column.string_size) {
            wrong("string of " + std::to_string(text.size()) + " bytes exceeds the column's " +
                  std::to_string(column.string_size));
          }
          if (text.find('\0') != std::string::npos) wrong("string contains a NUL character");
          std::memcpy(cell, text.data(), text.size());
          break;
        }
      }
    }
  }
  return buffer;
}

}  // namespace

// ================================================================ Hdf5File

Hdf5File::Hdf5File(std::filesystem::path path, std::int64_t id, bool read_only)
    : path_(std::move(path)), id_(id), read_only_(read_only) {}

Hdf5File::Hdf5File(Hdf5File&& other) noexcept
    : path_(std::move(other.path_)),
      id_(std::exchange(other.id_, -1)),
      read_only_(other.read_only_),
      gzip_level_(other.gzip_level_) {}

Hdf5File& Hdf5File::operator=(Hdf5File&& other) noexcept {
  if (this != &other) {
    if (id_ >= 0) {
      disable_automatic_error_printing();
      if (H5Fclose(id_) < 0) H5Eclear2(H5E_DEFAULT);
    }
    path_ = std::move(other.path_);
    id_ = std::exchange(other.id_, -1);
    read_only_ = other.read_only_;
    gzip_level_ = other.gzip_level_;
  }
  return *this;
}

Hdf5File::~Hdf5File() {
  if (id_ < 0) return;
  disable_automatic_error_printing();
  if (H5Fclose(id_) < 0) H5Eclear2(H5E_DEFAULT);
}

namespace {

// Why a file could not be opened, in words, from the file system's view; HDF5's
// own reason follows it in the message.
std::string file_problem(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) return " (no such file)";
  if (fs::is_directory(status)) return " (it is a directory)";
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  H5Eclear2(H5E_DEFAULT);
  if (is_hdf5 == 0) return " (not an HDF5 file)";
  return "";
}

}  // namespace

Hdf5File Hdf5File::create(const std::filesystem::path& path, CreateMode mode) {
  disable_automatic_error_printing();
  const unsigned flags = mode == CreateMode::kTruncate ? H5F_ACC_TRUNC : H5F_ACC_EXCL;
  const hid_t id = H5Fcreate(path.c_str(), flags, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) {
    const std::string reason = take_hdf5_reason();
    std::error_code error;
    std::string problem;
    if (fs::is_directory(path, error)) {
      problem = " (it is a directory)";
    } else if (mode == CreateMode::kFailIfExists && fs::exists(path, error)) {
      problem = " (file exists)";
    } else if (path.has_parent_path() && !fs::is_directory(path.parent_path(), error)) {
      problem = " (no such directory " + in_quotes(path.parent_path().string()) + ")";
    }
    throw std::runtime_error("cannot create HDF5 file " + in_quotes(path.string()) + problem +
                             ": " + reason);
  }
  return Hdf5File(path, id, false);
}

Hdf5File Hdf5File::open(const std::filesystem::path& path, bool read_only) {
  disable_automatic_error_printing();
  const hid_t id = H5Fopen(path.c_str(), read_only ? H5F_ACC_RDONLY : H5F_ACC_RDWR, H5P_DEFAULT);
  if (id < 0) {
    const std::string reason = take_hdf5_reason();
    throw std::runtime_error("cannot open HDF5 file " + in_quotes(path.string()) +
                             file_problem(path) + ": " + reason);
  }
  return Hdf5File(path, id, read_only);
}

Hdf5File Hdf5File::open_read_only(const std::filesystem::path& path) {
  return open(path, true);
}

Hdf5File Hdf5File::open_read_write(const std::filesystem::path& path) {
  return open(path, false);
}

void Hdf5File::set_gzip_level(int level) {
  if (level < 0 || level > 9) {
    throw std::invalid_argument("gzip level must be in [0, 9], got " + std::to_string(level));
  }
  gzip_level_ = level;
}

void Hdf5File::flush() {
  disable_automatic_error_printing();
  if (H5Fflush(id_, H5F_SCOPE_GLOBAL) < 0) throw_hdf5_error(path_, "flush", "/");
}

void Hdf5File::require_new_object(std::string_view object_path) const {
  if (read_only_) throw_store_error(path_, object_path, "file is open read-only");
  const Lookup lookup = look_up(Context{id_, path_}, normalized(object_path, path_));
  if (lookup.found) throw_store_error(path_, object_path, "already exists");
  if (!lookup.blocking_parent.empty()) {
    throw_store_error(path_, object_path,
                      "parent " + in_quotes(lookup.blocking_parent) + " is not a group");
  }
}

bool Hdf5File::exists(std::string_view path) const {
  return object_exists(Context{id_, path_}, normalized(path, path_));
}

void Hdf5File::create_group(std::string_view path) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  const Context where{id_, path_};
  const Handle lcpl = intermediate_groups_lcpl(where, name);
  checked(H5Gcreate2(id_, name.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose, where,
          "create group", name);
}

void Hdf5File::remove(std::string_view path) {
  const std::string name = normalized(path, path_);
  if (read_only_) throw_store_error(path_, name, "file is open read-only");
  if (name == "/") throw_store_error(path_, name, "cannot remove the root group");
  const Context where{id_, path_};
  require_existing(where, name);
  check(H5Ldelete(id_, name.c_str(), H5P_DEFAULT), where, "remove", name);
}

void Hdf5File::detach(std::string_view path) {
  const std::string name = normalized(path, path_);
  if (read_only_) throw_store_error(path_, name, "file is open read-only");
  if (name == "/") throw_store_error(path_, name, "cannot detach the root group");
  const Context where{id_, path_};
  require_existing(where, name);
  // One extra reference keeps the object alive when its link goes, so HDF5
  // never walks (and never frees) what is below it. Only the object's own
  // header is read.
  const Handle object =
      checked(H5Oopen(id_, name.c_str(), H5P_DEFAULT), H5Oclose, where, "open", name);
  check(H5Oincr_refcount(object.get()), where, "detach", name);
  check(H5Ldelete(id_, name.c_str(), H5P_DEFAULT), where, "detach", name);
}

void Hdf5File::move(std::string_view from, std::string_view to) {
  const std::string source = normalized(from, path_);
  const std::string target = normalized(to, path_);
  if (read_only_) throw_store_error(path_, source, "file is open read-only");
  if (source == "/") throw_store_error(path_, source, "cannot move the root group");
  const Context where{id_, path_};
  require_existing(where, source);
  require_new_object(target);
  const Handle lcpl = intermediate_groups_lcpl(where, target);
  check(H5Lmove(id_, source.c_str(), id_, target.c_str(), lcpl.get(), H5P_DEFAULT), where,
        "move " + in_quotes(source) + " to", target);
}

std::vector<std::int64_t> Hdf5File::dataset_shape(std::string_view path) const {
  const std::string name = normalized(path, path_);
  const Context where{id_, path_};
  const Handle dataset = open_dataset(where, name);
  const Handle space = dataset_space(where, dataset, name);
  std::vector<std::int64_t> shape;
  for (const hsize_t dim : space_dims(where, space, name)) {
    shape.push_back(static_cast<std::int64_t>(dim));
  }
  return shape;
}

// ---------------------------------------------------------------- numeric

void Hdf5File::write_vector(std::string_view path, std::span<const double> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  write_vector_of(Context{id_, path_}, name, values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const float> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  write_vector_of(Context{id_, path_}, name, values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const std::int32_t> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  write_vector_of(Context{id_, path_}, name, values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const std::int64_t> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  write_vector_of(Context{id_, path_}, name, values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const std::uint8_t> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  write_vector_of(Context{id_, path_}, name, values, gzip_level_);
}

template <class T>
std::vector<T> Hdf5File::read_vector(std::string_view path) const {
  std::vector<hsize_t> dims;
  return read_numeric<T>(Context{id_, path_}, normalized(path, path_), 1, dims);
}

template std::vector<double> Hdf5File::read_vector<double>(std::string_view) const;
template std::vector<float> Hdf5File::read_vector<float>(std::string_view) const;
template std::vector<std::int32_t> Hdf5File::read_vector<std::int32_t>(std::string_view) const;
template std::vector<std::int64_t> Hdf5File::read_vector<std::int64_t>(std::string_view) const;
template std::vector<std::uint8_t> Hdf5File::read_vector<std::uint8_t>(std::string_view) const;

void Hdf5File::write_matrix(std::string_view path, std::int64_t rows, std::int64_t cols,
                            std::span<const double> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  write_matrix_of(Context{id_, path_}, name, rows, cols, values, gzip_level_);
}

void Hdf5File::write_matrix(std::string_view path, std::int64_t rows, std::int64_t cols,
                            std::span<const std::int32_t> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  write_matrix_of(Context{id_, path_}, name, rows, cols, values, gzip_level_);
}

template <class T>
RowMajorArray<T> Hdf5File::read_matrix(std::string_view path) const {
  std::vector<hsize_t> dims;
  RowMajorArray<T> matrix;
  matrix.data = read_numeric<T>(Context{id_, path_}, normalized(path, path_), 2, dims);
  matrix.rows = static_cast<std::int64_t>(dims[0]);
  matrix.cols = static_cast<std::int64_t>(dims[1]);
  return matrix;
}

template RowMajorArray<double> Hdf5File::read_matrix<double>(std::string_view) const;
template RowMajorArray<std::int32_t> Hdf5File::read_matrix<std::int32_t>(std::string_view) const;

// ---------------------------------------------------------------- strings

void Hdf5File::write_strings(std::string_view path, std::span<const std::string> values) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  const Context where{id_, path_};
  std::vector<const char*> pointers;
  pointers.reserve(values.size());
  for (const std::string& value : values) {
    require_no_nul(where, name, value);
    pointers.push_back(value.c_str());
  }
  const Handle type = variable_string_type(where, name);
  const hsize_t dims[1] = {values.size()};
  write_dataset(where, name, dims, type.get(), type.get(), sizeof(hvl_t), gzip_level_,
                pointers.data());
}

std::vector<std::string> Hdf5File::read_strings(std::string_view path) const {
  const std::string name = normalized(path, path_);
  const Context where{id_, path_};
  const Handle dataset = open_dataset(where, name);
  const Handle type = dataset_type(where, dataset, name);
  if (H5Tget_class(type.get()) != H5T_STRING) {
    throw_store_error(path_, name, "holds " + describe_type(type.get()) + ", not strings");
  }
  const Handle space = dataset_space(where, dataset, name);
  const std::vector<hsize_t> dims = space_dims(where, space, name);
  if (dims.size() != 1) {
    throw_store_error(path_, name,
                      "has rank " + std::to_string(dims.size()) + ", expected 1 (strings)");
  }
  const std::size_t count = element_count(dims);
  std::vector<std::string> values;
  values.reserve(count);
  if (count == 0) return values;
  if (H5Tis_variable_str(type.get()) > 0) {
    const Handle memory_type = variable_string_type(where, name);
    std::vector<char*> pointers(count, nullptr);
    check(H5Dread(dataset.get(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()),
          where, "read dataset", name);
    for (const char* pointer : pointers) values.emplace_back(pointer == nullptr ? "" : pointer);
    H5Dvlen_reclaim(memory_type.get(), space.get(), H5P_DEFAULT, pointers.data());
  } else {
    const std::size_t size = H5Tget_size(type.get());
    const H5T_str_t padding = H5Tget_strpad(type.get());
    std::vector<char> buffer(count * size);
    check(H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()), where,
          "read dataset", name);
    for (std::size_t i = 0; i < count; ++i) {
      values.push_back(decode_fixed_string(buffer.data() + i * size, size, padding));
    }
  }
  return values;
}

// ---------------------------------------------------------------- attributes

bool Hdf5File::has_attribute(std::string_view object_path, std::string_view name) const {
  const std::string object = normalized(object_path, path_);
  const Context where{id_, path_};
  require_existing(where, object);
  const htri_t found =
      H5Aexists_by_name(id_, object.c_str(), std::string(name).c_str(), H5P_DEFAULT);
  if (found < 0) throw_hdf5_error(path_, "look up attribute " + in_quotes(name) + " of", object);
  return found > 0;
}

void Hdf5File::remove_attribute(std::string_view object_path, std::string_view name) {
  const std::string object = normalized(object_path, path_);
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (!has_attribute(object, name)) {
    throw_store_error(path_, object, "has no attribute " + in_quotes(name));
  }
  check(H5Adelete_by_name(id_, object.c_str(), std::string(name).c_str(), H5P_DEFAULT),
        Context{id_, path_}, "remove attribute " + in_quotes(name) + " of", object);
}

namespace {

// Creates attribute `name` on an existing object and writes it: a scalar when
// dims is empty, else a 1-D array of dims[0] elements.
void write_attribute(const Context& where, const std::string& object, const std::string& name,
                     hid_t file_type, hid_t memory_type, const void* data,
                     const std::vector<hsize_t>& dims) {
  const Handle space =
      dims.empty() ? checked(H5Screate(H5S_SCALAR), H5Sclose, where, "create dataspace for", object)
                   : checked(H5Screate_simple(1, dims.data(), nullptr), H5Sclose, where,
                             "create dataspace for", object);
  const Handle attribute =
      checked(H5Acreate_by_name(where.file, object.c_str(), name.c_str(), file_type, space.get(),
                                H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, where, "create attribute " + in_quotes(name) + " of", object);
  if (!dims.empty() && dims.front() == 0) return;
  check(H5Awrite(attribute.get(), memory_type, data), where,
        "write attribute " + in_quotes(name) + " of", object);
}

}  // namespace

void Hdf5File::write_string_attribute(std::string_view object_path, std::string_view name,
                                      std::string_view value) {
  const std::string object = normalized(object_path, path_);
  const Context where{id_, path_};
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (has_attribute(object, name)) {
    throw_store_error(path_, object, "attribute " + in_quotes(name) + " already exists");
  }
  require_no_nul(where, object, value);
  const std::string text(value);
  const char* pointer = text.c_str();
  const Handle type = variable_string_type(where, object);
  write_attribute(where, object, std::string(name), type.get(), type.get(), &pointer, {});
}

void Hdf5File::write_double_attribute(std::string_view object_path, std::string_view name,
                                      double value) {
  const std::string object = normalized(object_path, path_);
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (has_attribute(object, name)) {
    throw_store_error(path_, object, "attribute " + in_quotes(name) + " already exists");
  }
  write_attribute(Context{id_, path_}, object, std::string(name), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                  &value, {});
}

void Hdf5File::write_int64_attribute(std::string_view object_path, std::string_view name,
                                     std::int64_t value) {
  const std::string object = normalized(object_path, path_);
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (has_attribute(object, name)) {
    throw_store_error(path_, object, "attribute " + in_quotes(name) + " already exists");
  }
  write_attribute(Context{id_, path_}, object, std::string(name), H5T_STD_I64LE, H5T_NATIVE_INT64,
                  &value, {});
}

void Hdf5File::write_int64_array_attribute(std::string_view object_path, std::string_view name,
                                           std::span<const std::int64_t> values) {
  const std::string object = normalized(object_path, path_);
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (has_attribute(object, name)) {
    throw_store_error(path_, object, "attribute " + in_quotes(name) + " already exists");
  }
  write_attribute(Context{id_, path_}, object, std::string(name), H5T_STD_I64LE, H5T_NATIVE_INT64,
                  values.data(), {values.size()});
}

std::string Hdf5File::read_string_attribute(std::string_view object_path,
                                            std::string_view name) const {
  const std::string object = normalized(object_path, path_);
  const std::string attribute_name(name);
  const Context where{id_, path_};
  const Handle attribute = open_attribute(where, object, attribute_name);
  const Handle type =
      checked(H5Aget_type(attribute.get()), H5Tclose, where,
              "get the type of attribute " + in_quotes(attribute_name) + " of", object);
  if (H5Tget_class(type.get()) != H5T_STRING) {
    throw_store_error(path_, object,
                      "attribute " + in_quotes(attribute_name) + " holds " +
                          describe_type(type.get()) + ", not a string");
  }
  if (attribute_size(where, attribute, object, attribute_name) != 1) {
    throw_store_error(path_, object,
                      "attribute " + in_quotes(attribute_name) + " is not a single string");
  }
  if (H5Tis_variable_str(type.get()) > 0) {
    const Handle memory_type = variable_string_type(where, object);
    char* pointer = nullptr;
    check(H5Aread(attribute.get(), memory_type.get(), &pointer), where,
          "read attribute " + in_quotes(attribute_name) + " of", object);
    std::string value = pointer == nullptr ? "" : pointer;
    const Handle space = checked(H5Screate(H5S_SCALAR), H5Sclose, where, "read", object);
    H5Dvlen_reclaim(memory_type.get(), space.get(), H5P_DEFAULT, &pointer);
    return value;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::vector<char> buffer(size);
  check(H5Aread(attribute.get(), type.get(), buffer.data()), where,
        "read attribute " + in_quotes(attribute_name) + " of", object);
  return decode_fixed_string(buffer.data(), size, H5Tget_strpad(type.get()));
}

double Hdf5File::read_double_attribute(std::string_view object_path, std::string_view name) const {
  return read_scalar_attribute<double>(Context{id_, path_}, normalized(object_path, path_),
                                       std::string(name));
}

std::int64_t Hdf5File::read_int64_attribute(std::string_view object_path,
                                            std::string_view name) const {
  return read_scalar_attribute<std::int64_t>(Context{id_, path_}, normalized(object_path, path_),
                                             std::string(name));
}

std::vector<std::int64_t> Hdf5File::read_int64_array_attribute(std::string_view object_path,
                                                               std::string_view name) const {
  return read_numeric_attribute<std::int64_t>(Context{id_, path_}, normalized(object_path, path_),
                                              std::string(name));
}

// ---------------------------------------------------------------- CSR

void Hdf5File::write_csr(std::string_view path, std::int64_t rows, std::int64_t cols,
                         std::span<const std::int64_t> indptr,
                         std::span<const std::int32_t> indices, std::span<const double> values,
                         std::string_view values_name) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  check_csr(path_, name, rows, cols, indptr, indices, values.size());
  create_group(name);
  write_vector(join(name, "indptr"), indptr);
  write_vector(join(name, "indices"), indices);
  write_vector(join(name, values_name), values);
  const std::int64_t shape[2] = {rows, cols};
  write_int64_array_attribute(name, "shape", shape);
}

void Hdf5File::write_csr(std::string_view path, const CsrMatrix& matrix,
                         std::string_view values_name) {
  if (!matrix.isCompressed()) {
    CsrMatrix compressed = matrix;
    compressed.makeCompressed();
    write_csr(path, compressed, values_name);
    return;
  }
  const auto nnz = static_cast<std::size_t>(matrix.nonZeros());
  std::vector<std::int64_t> indptr(matrix.outerIndexPtr(),
                                   matrix.outerIndexPtr() + matrix.rows() + 1);
  write_csr(path, matrix.rows(), matrix.cols(), indptr,
            std::span<const std::int32_t>(matrix.innerIndexPtr(), nnz),
            std::span<const double>(matrix.valuePtr(), nnz), values_name);
}

CsrArrays Hdf5File::read_csr(std::string_view path, std::string_view values_name) const {
  const std::string name = normalized(path, path_);
  CsrArrays csr;
  const std::vector<std::int64_t> shape = read_int64_array_attribute(name, "shape");
  if (shape.size() != 2) {
    throw_store_error(path_, name, "attribute 'shape' does not have 2 elements");
  }
  csr.rows = shape[0];
  csr.cols = shape[1];
  csr.indptr = read_vector<std::int64_t>(join(name, "indptr"));
  csr.indices = read_vector<std::int32_t>(join(name, "indices"));
  csr.data = read_vector<double>(join(name, values_name));
  check_csr(path_, name, csr.rows, csr.cols, csr.indptr, csr.indices, csr.data.size());
  return csr;
}

CsrMatrix Hdf5File::read_csr_matrix(std::string_view path, std::string_view values_name) const {
  const CsrArrays csr = read_csr(path, values_name);
  constexpr auto kMaxIndex = std::numeric_limits<std::int32_t>::max();
  if (csr.rows > kMaxIndex || csr.cols > kMaxIndex ||
      csr.data.size() > static_cast<std::size_t>(kMaxIndex)) {
    throw_store_error(path_, normalized(path, path_),
                      "too large for a sparse matrix with int32 indices");
  }
  const std::vector<std::int32_t> outer(csr.indptr.begin(), csr.indptr.end());
  const Eigen::Map<const CsrMatrix> map(csr.rows, csr.cols,
                                        static_cast<Eigen::Index>(csr.data.size()), outer.data(),
                                        csr.indices.data(), csr.data.data());
  return CsrMatrix(map);
}

// ---------------------------------------------------------------- tables

void Hdf5File::create_table(std::string_view path, std::span<const TableColumn> columns,
                            std::int64_t chunk_rows) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  const Context where{id_, path_};
  check_columns(where, name, columns);
  if (chunk_rows < 1) throw_store_error(path_, name, "chunk_rows must be >= 1");
  const Handle type = row_type(where, name, columns, true);
  const hsize_t dims[1] = {0};
  const hsize_t max_dims[1] = {H5S_UNLIMITED};
  const Handle space =
      checked(H5Screate_simple(1, dims, max_dims), H5Sclose, where, "create dataspace for", name);
  const Handle dcpl = make_property_list(H5P_DATASET_CREATE, where, name);
  const hsize_t chunk[1] = {static_cast<hsize_t>(chunk_rows)};
  // No filters: appending to a compressed chunk rewrites the whole chunk in
  // place, and a kill in the middle would destroy rows already flushed. An
  // unfiltered chunk keeps its address and the bytes of earlier rows.
  check(H5Pset_chunk(dcpl.get(), 1, chunk), where, "set chunks of", name);
  const Handle lcpl = intermediate_groups_lcpl(where, name);
  checked(
      H5Dcreate2(id_, name.c_str(), type.get(), space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
      H5Dclose, where, "create table", name);
}

std::vector<TableColumn> Hdf5File::read_table_columns(std::string_view path) const {
  const std::string name = normalized(path, path_);
  const Context where{id_, path_};
  const Handle dataset = open_dataset(where, name);
  return table_columns(where, name, dataset);
}

void Hdf5File::append_rows(std::string_view path, std::span<const TableRow> rows) {
  const std::string name = normalized(path, path_);
  if (read_only_) throw_store_error(path_, name, "file is open read-only");
  const Context where{id_, path_};
  const Handle dataset = open_dataset(where, name);
  const std::vector<TableColumn> columns = table_columns(where, name, dataset);
  // Every row is checked before the table grows, so a bad batch adds nothing.
  const std::vector<unsigned char> buffer = pack_rows(where, name, columns, rows);
  if (rows.empty()) return;
  const Handle old_space = dataset_space(where, dataset, name);
  const std::vector<hsize_t> old_dims = space_dims(where, old_space, name);
  if (old_dims.size() != 1) throw_store_error(path_, name, "a table must be 1-D");
  const hsize_t start[1] = {old_dims[0]};
  const hsize_t count[1] = {rows.size()};
  const hsize_t new_dims[1] = {old_dims[0] + rows.size()};
  check(H5Dset_extent(dataset.get(), new_dims), where, "extend table", name);
  const Handle file_space = dataset_space(where, dataset, name);
  check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
        where, "select rows of", name);
  const Handle memory_space =
      checked(H5Screate_simple(1, count, nullptr), H5Sclose, where, "create dataspace for", name);
  const Handle memory_type = row_type(where, name, columns, false);
  check(H5Dwrite(dataset.get(), memory_type.get(), memory_space.get(), file_space.get(),
                 H5P_DEFAULT, buffer.data()),
        where, "append rows to", name);
}

std::vector<TableRow> Hdf5File::read_table(std::string_view path) const {
  const std::string name = normalized(path, path_);
  const Context where{id_, path_};
  const Handle dataset = open_dataset(where, name);
  const std::vector<TableColumn> columns = table_columns(where, name, dataset);
  const Handle space = dataset_space(where, dataset, name);
  const std::vector<hsize_t> dims = space_dims(where, space, name);
  if (dims.size() != 1) throw_store_error(path_, name, "a table must be 1-D");
  const std::size_t count = element_count(dims);
  const std::vector<std::size_t> offsets = column_offsets(columns);
  const std::size_t row_size = offsets.back();
  std::vector<unsigned char> buffer(count * row_size);
  if (count > 0) {
    const Handle memory_type = row_type(where, name, columns, false);
    check(H5Dread(dataset.get(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()),
          where, "read table", name);
  }
  std::vector<TableRow> rows(count);
  for (std::size_t r = 0; r < count; ++r) {
    rows[r].reserve(columns.size());
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const unsigned char* cell = buffer.data() + r * row_size + offsets[c];
      switch (columns[c].type) {
        case ColumnType::kInt32: {
          std::int32_t value = 0;
          std::memcpy(&value, cell, sizeof(value));
          rows[r].emplace_back(value);
          break;
        }
        case ColumnType::kInt64: {
          std::int64_t value = 0;
          std::memcpy(&value, cell, sizeof(value));
          rows[r].emplace_back(value);
          break;
        }
        case ColumnType::kFloat64: {
          double value = 0;
          std::memcpy(&value, cell, sizeof(value));
          rows[r].emplace_back(value);
          break;
        }
        case ColumnType::kString:
          rows[r].emplace_back(decode_fixed_string(reinterpret_cast<const char*>(cell),
                                                   columns[c].string_size, H5T_STR_NULLPAD));
          break;
      }
    }
  }
  return rows;
}

}  // namespace ggk::engine
