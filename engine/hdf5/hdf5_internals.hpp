#pragma once
// Internal to engine/store: the helpers the parts of Hdf5File share (hdf5_file.cpp,
// hdf5_datasets.cpp, hdf5_attributes.cpp, hdf5_csr.cpp, hdf5_tables.cpp,
// hdf5_images.cpp, hdf5_introspection.cpp). Not for other rooms: hdf5_file.hpp is the
// store's API. Implemented in hdf5_internals.cpp (templates here).
//  - errors: HDF5's error stack collected into the messages we throw;
//  - Handle: one HDF5 identifier, closed with its H5?close; checked()/check();
//  - Context: the file an operation works on, to name it in errors;
//  - paths: normalising and looking up object paths;
//  - types: naming and building HDF5 types, fixed/variable-length strings;
//  - datasets: opening one, its type and shape, the typed read of a numeric array.
// Thread-safety: as Hdf5File's (none; the error printing switch is per thread).

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/single_quoted.hpp"

namespace ggk::engine::hdf5_internals {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- errors

// Debian builds HDF5 thread-safe, where the error stack and its automatic
// printing are per thread: switch printing off once in every thread that
// calls HDF5 through this file (take_hdf5_reason() reports instead).
void disable_automatic_error_printing();

// HDF5's reason for the last failure, from its error stack (which is then
// cleared): the outermost description says what failed, the innermost why.
std::string take_hdf5_reason();

// A failure of an HDF5 call: names the file, what was attempted, the object
// and HDF5's reason.
[[noreturn]] void throw_hdf5_error(const fs::path& file, std::string_view what,
                                   std::string_view object_path);

// A misuse detected before calling HDF5 (wrong shape, existing path, ...).
[[noreturn]] void throw_store_error(const fs::path& file, std::string_view object_path,
                                    std::string_view problem);

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
               std::string_view object_path);

void check(herr_t status, const Context& where, std::string_view what,
           std::string_view object_path);

Handle make_property_list(hid_t property_class, const Context& where, std::string_view object_path);

// Link creation properties that create missing parent groups.
Handle intermediate_groups_lcpl(const Context& where, std::string_view object_path);

Handle open_dataset(const Context& where, const std::string& path);

Handle dataset_type(const Context& where, const Handle& dataset, const std::string& path);

Handle dataset_space(const Context& where, const Handle& dataset, const std::string& path);

std::vector<hsize_t> space_dims(const Context& where, const Handle& space, const std::string& path);

std::size_t element_count(std::span<const hsize_t> dims);

// ---------------------------------------------------------------- paths

// "a/b" and "/a/b/" both become "/a/b"; "" is an error.
std::string normalized(std::string_view path, const fs::path& file);

std::string join(const std::string& parent, std::string_view child);

// The longest existing prefix of a path that is not a group ("" if none):
// nothing can exist or be created below it.
struct Lookup {
  bool found = false;
  std::string blocking_parent;
};

Lookup look_up(const Context& where, const std::string& path);

bool object_exists(const Context& where, const std::string& path);

void require_existing(const Context& where, const std::string& path);

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

std::string describe_type(hid_t type);

template <class T>
bool has_numeric_type(hid_t type) {
  if (H5Tget_class(type) != NumericType<T>::kClass || H5Tget_size(type) != sizeof(T)) return false;
  return NumericType<T>::kClass != H5T_INTEGER || H5Tget_sign(type) == NumericType<T>::kSign;
}

// Variable-length UTF-8 string type (as h5py writes str).
Handle variable_string_type(const Context& where, std::string_view object_path);

// Fixed-length, NUL-padded UTF-8 string type of `size` bytes.
Handle fixed_string_type(const Context& where, std::size_t size, std::string_view object_path);

// The text of one fixed-length string element of `size` bytes.
std::string decode_fixed_string(const char* bytes, std::size_t size, H5T_str_t padding);

void require_no_nul(const Context& where, std::string_view object_path, std::string_view text);

// ---------------------------------------------------------------- datasets

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

}  // namespace ggk::engine::hdf5_internals
