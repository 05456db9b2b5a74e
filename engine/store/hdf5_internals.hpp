#pragma once
// Internal to engine/store: the helpers the parts of Hdf5File share (hdf5_file.cpp,
// hdf5_datasets.cpp, hdf5_attributes.cpp, hdf5_csr.cpp, hdf5_tables.cpp,
// hdf5_introspection.cpp). Not for other rooms: hdf5_file.hpp is the store's API.
//  - errors: HDF5's error stack collected into the messages we throw;
//  - Handle: one HDF5 identifier, closed with its H5?close; checked()/check();
//  - Context: the file an operation works on, to name it in errors;
//  - paths: normalising and looking up object paths;
//  - types: naming and building HDF5 types, fixed/variable-length strings;
//  - datasets: chunking, compression and the typed read/write of numeric arrays.

#include <hdf5.h>

#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/store/hdf5_file.hpp"

namespace ggk::engine::hdf5_internals {

namespace fs = std::filesystem;

// Chunks of about this many bytes: large enough for gzip to work well, small
// enough that reading one value does not inflate megabytes.
inline constexpr std::size_t kTargetChunkBytes = 256 * 1024;

// ---------------------------------------------------------------- errors

// Debian builds HDF5 thread-safe, where the error stack and its automatic
// printing are per thread: switch printing off once in every thread that
// calls HDF5 through this file (take_hdf5_reason() reports instead).
inline void disable_automatic_error_printing() {
  thread_local bool disabled = false;
  if (!disabled) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    disabled = true;
  }
}

inline herr_t collect_error_description(unsigned /*depth*/, const H5E_error2_t* error, void* data) {
  auto& descriptions = *static_cast<std::vector<std::string>*>(data);
  if (error->desc != nullptr && error->desc[0] != '\0' &&
      (descriptions.empty() || descriptions.back() != error->desc)) {
    descriptions.emplace_back(error->desc);
  }
  return 0;
}

// HDF5's reason for the last failure, from its error stack (which is then
// cleared): the outermost description says what failed, the innermost why.
inline std::string take_hdf5_reason() {
  std::vector<std::string> descriptions;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect_error_description, &descriptions);
  H5Eclear2(H5E_DEFAULT);
  if (descriptions.empty()) return "HDF5 gave no reason";
  std::string reason = descriptions.front();
  if (descriptions.size() > 1) reason += ": " + descriptions.back();
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  return reason;
}

inline std::string in_quotes(std::string_view text) {
  // Appended piece by piece: GCC 12 at -O3 reports a false -Wrestrict on
  // "'" + std::string(...) (GCC bug 105329).
  std::string result;
  result.reserve(text.size() + 2);
  result += '\'';
  result += text;
  result += '\'';
  return result;
}

inline std::string file_prefix(const fs::path& file) {
  return "HDF5 file " + in_quotes(file.string());
}

// A failure of an HDF5 call: names the file, what was attempted, the object
// and HDF5's reason.
[[noreturn]] inline void throw_hdf5_error(const fs::path& file, std::string_view what,
                                          std::string_view object_path) {
  throw std::runtime_error(file_prefix(file) + ": cannot " + std::string(what) + " " +
                           in_quotes(object_path) + ": " + take_hdf5_reason());
}

// A misuse detected before calling HDF5 (wrong shape, existing path, ...).
[[noreturn]] inline void throw_store_error(const fs::path& file, std::string_view object_path,
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

inline Handle checked(hid_t id, Handle::Closer closer, const Context& where, std::string_view what,
                      std::string_view object_path) {
  if (id < 0) throw_hdf5_error(where.file_path, what, object_path);
  return Handle(id, closer);
}

inline void check(herr_t status, const Context& where, std::string_view what,
                  std::string_view object_path) {
  if (status < 0) throw_hdf5_error(where.file_path, what, object_path);
}

inline Handle make_property_list(hid_t property_class, const Context& where,
                                 std::string_view object_path) {
  return checked(H5Pcreate(property_class), H5Pclose, where, "create property list for",
                 object_path);
}

// Link creation properties that create missing parent groups.
inline Handle intermediate_groups_lcpl(const Context& where, std::string_view object_path) {
  Handle lcpl = make_property_list(H5P_LINK_CREATE, where, object_path);
  check(H5Pset_create_intermediate_group(lcpl.get(), 1), where, "set up parents of", object_path);
  return lcpl;
}

inline Handle open_dataset(const Context& where, const std::string& path) {
  return checked(H5Dopen2(where.file, path.c_str(), H5P_DEFAULT), H5Dclose, where, "open dataset",
                 path);
}

inline Handle dataset_type(const Context& where, const Handle& dataset, const std::string& path) {
  return checked(H5Dget_type(dataset.get()), H5Tclose, where, "get the type of", path);
}

inline Handle dataset_space(const Context& where, const Handle& dataset, const std::string& path) {
  return checked(H5Dget_space(dataset.get()), H5Sclose, where, "get the shape of", path);
}

inline std::vector<hsize_t> space_dims(const Context& where, const Handle& space,
                                       const std::string& path) {
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) throw_hdf5_error(where.file_path, "get the rank of", path);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0) {
    throw_hdf5_error(where.file_path, "get the shape of", path);
  }
  return dims;
}

inline std::size_t element_count(std::span<const hsize_t> dims) {
  std::size_t count = 1;
  for (const hsize_t dim : dims) count *= static_cast<std::size_t>(dim);
  return count;
}

// ---------------------------------------------------------------- paths

// "a/b" and "/a/b/" both become "/a/b"; "" is an error.
inline std::string normalized(std::string_view path, const fs::path& file) {
  if (path.empty()) throw_store_error(file, path, "empty object path");
  std::string result = path.front() == '/' ? std::string(path) : "/" + std::string(path);
  while (result.size() > 1 && result.back() == '/') result.pop_back();
  return result;
}

inline std::string join(const std::string& parent, std::string_view child) {
  return parent == "/" ? parent + std::string(child) : parent + "/" + std::string(child);
}

// The longest existing prefix of a path that is not a group ("" if none):
// nothing can exist or be created below it.
struct Lookup {
  bool found = false;
  std::string blocking_parent;
};

inline Lookup look_up(const Context& where, const std::string& path) {
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

inline bool object_exists(const Context& where, const std::string& path) {
  return look_up(where, path).found;
}

inline void require_existing(const Context& where, const std::string& path) {
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

inline std::string describe_type(hid_t type) {
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
inline Handle variable_string_type(const Context& where, std::string_view object_path) {
  Handle type = checked(H5Tcopy(H5T_C_S1), H5Tclose, where, "make string type for", object_path);
  check(H5Tset_size(type.get(), H5T_VARIABLE), where, "make string type for", object_path);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "make string type for", object_path);
  return type;
}

// Fixed-length, NUL-padded UTF-8 string type of `size` bytes.
inline Handle fixed_string_type(const Context& where, std::size_t size,
                                std::string_view object_path) {
  Handle type = checked(H5Tcopy(H5T_C_S1), H5Tclose, where, "make string type for", object_path);
  check(H5Tset_size(type.get(), size), where, "make string type for", object_path);
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), where, "make string type for", object_path);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "make string type for", object_path);
  return type;
}

// The text of one fixed-length string element of `size` bytes.
inline std::string decode_fixed_string(const char* bytes, std::size_t size, H5T_str_t padding) {
  std::size_t length = 0;
  while (length < size && bytes[length] != '\0') ++length;
  if (padding == H5T_STR_SPACEPAD) {
    while (length > 0 && bytes[length - 1] == ' ') --length;
  }
  return std::string(bytes, length);
}

inline void require_no_nul(const Context& where, std::string_view object_path,
                           std::string_view text) {
  if (text.find('\0') != std::string_view::npos) {
    throw_store_error(where.file_path, object_path, "string contains a NUL character");
  }
}

// ---------------------------------------------------------------- datasets

// Chunk shape of about kTargetChunkBytes for a non-empty dataset; every chunk
// dimension is >= 1 and <= the dataset's (HDF5 requires both for fixed sizes).
inline std::vector<hsize_t> chunk_shape(std::span<const hsize_t> dims, std::size_t element_size) {
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
inline Handle compressed_dcpl(const Context& where, std::span<const hsize_t> dims,
                              std::size_t element_size, int gzip_level,
                              std::string_view object_path) {
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
inline void write_dataset(const Context& where, const std::string& path,
                          std::span<const hsize_t> dims, hid_t file_type, hid_t memory_type,
                          std::size_t element_size, int gzip_level, const void* data) {
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

}  // namespace ggk::engine::hdf5_internals
