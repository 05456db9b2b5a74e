#include "engine/hdf5/hdf5_file.hpp"

#include <hdf5.h>

#include "engine/hdf5/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of this file's parts

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- attributes

Handle open_attribute(const Context& where, const std::string& object_path,
                      const std::string& name) {
  require_existing(where, object_path);
  return checked(
      H5Aopen_by_name(where.file, object_path.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose, where, "open attribute " + single_quoted(name) + " of", object_path);
}

// Number of elements of an attribute (1 for a scalar).
std::size_t attribute_size(const Context& where, const Handle& attribute,
                           const std::string& object_path, const std::string& name) {
  const Handle space =
      checked(H5Aget_space(attribute.get()), H5Sclose, where,
              "get the shape of attribute " + single_quoted(name) + " of", object_path);
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  if (count < 0) {
    throw_hdf5_error(where.file_path, "get the size of attribute " + single_quoted(name) + " of",
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
  const Handle type =
      checked(H5Aget_type(attribute.get()), H5Tclose, where,
              "get the type of attribute " + single_quoted(name) + " of", object_path);
  if (H5Tget_class(type.get()) != NumericType<T>::kClass) {
    throw_store_error(where.file_path, object_path,
                      "attribute " + single_quoted(name) + " holds " + describe_type(type.get()) +
                          ", not " + NumericType<T>::kName);
  }
  std::vector<T> values(attribute_size(where, attribute, object_path, name));
  if (!values.empty()) {
    check(H5Aread(attribute.get(), NumericType<T>::memory(), values.data()), where,
          "read attribute " + single_quoted(name) + " of", object_path);
  }
  return values;
}

template <class T>
T read_scalar_attribute(const Context& where, const std::string& object_path,
                        const std::string& name) {
  const std::vector<T> values = read_numeric_attribute<T>(where, object_path, name);
  if (values.size() != 1) {
    throw_store_error(where.file_path, object_path,
                      "attribute " + single_quoted(name) + " has " + std::to_string(values.size()) +
                          " elements, expected 1");
  }
  return values.front();
}

}  // namespace

// ---------------------------------------------------------------- attributes

bool Hdf5File::has_attribute(std::string_view object_path, std::string_view name) const {
  const std::string object = normalized(object_path, path_);
  const Context where{id_, path_};
  require_existing(where, object);
  const htri_t found =
      H5Aexists_by_name(id_, object.c_str(), std::string(name).c_str(), H5P_DEFAULT);
  if (found < 0)
    throw_hdf5_error(path_, "look up attribute " + single_quoted(name) + " of", object);
  return found > 0;
}

void Hdf5File::remove_attribute(std::string_view object_path, std::string_view name) {
  const std::string object = normalized(object_path, path_);
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (!has_attribute(object, name)) {
    throw_store_error(path_, object, "has no attribute " + single_quoted(name));
  }
  check(H5Adelete_by_name(id_, object.c_str(), std::string(name).c_str(), H5P_DEFAULT),
        Context{id_, path_}, "remove attribute " + single_quoted(name) + " of", object);
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
              H5Aclose, where, "create attribute " + single_quoted(name) + " of", object);
  if (!dims.empty() && dims.front() == 0) return;
  check(H5Awrite(attribute.get(), memory_type, data), where,
        "write attribute " + single_quoted(name) + " of", object);
}

}  // namespace

void Hdf5File::write_string_attribute(std::string_view object_path, std::string_view name,
                                      std::string_view value) {
  const std::string object = normalized(object_path, path_);
  const Context where{id_, path_};
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (has_attribute(object, name)) {
    throw_store_error(path_, object, "attribute " + single_quoted(name) + " already exists");
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
    throw_store_error(path_, object, "attribute " + single_quoted(name) + " already exists");
  }
  write_attribute(Context{id_, path_}, object, std::string(name), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                  &value, {});
}

void Hdf5File::write_int64_attribute(std::string_view object_path, std::string_view name,
                                     std::int64_t value) {
  const std::string object = normalized(object_path, path_);
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (has_attribute(object, name)) {
    throw_store_error(path_, object, "attribute " + single_quoted(name) + " already exists");
  }
  write_attribute(Context{id_, path_}, object, std::string(name), H5T_STD_I64LE, H5T_NATIVE_INT64,
                  &value, {});
}

void Hdf5File::write_int64_array_attribute(std::string_view object_path, std::string_view name,
                                           std::span<const std::int64_t> values) {
  const std::string object = normalized(object_path, path_);
  if (read_only_) throw_store_error(path_, object, "file is open read-only");
  if (has_attribute(object, name)) {
    throw_store_error(path_, object, "attribute " + single_quoted(name) + " already exists");
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
              "get the type of attribute " + single_quoted(attribute_name) + " of", object);
  if (H5Tget_class(type.get()) != H5T_STRING) {
    throw_store_error(path_, object,
                      "attribute " + single_quoted(attribute_name) + " holds " +
                          describe_type(type.get()) + ", not a string");
  }
  if (attribute_size(where, attribute, object, attribute_name) != 1) {
    throw_store_error(path_, object,
                      "attribute " + single_quoted(attribute_name) + " is not a single string");
  }
  if (H5Tis_variable_str(type.get()) > 0) {
    const Handle memory_type = variable_string_type(where, object);
    char* pointer = nullptr;
    check(H5Aread(attribute.get(), memory_type.get(), &pointer), where,
          "read attribute " + single_quoted(attribute_name) + " of", object);
    std::string value = pointer == nullptr ? "" : pointer;
    const Handle space = checked(H5Screate(H5S_SCALAR), H5Sclose, where, "read", object);
    H5Dvlen_reclaim(memory_type.get(), space.get(), H5P_DEFAULT, &pointer);
    return value;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::vector<char> buffer(size);
  check(H5Aread(attribute.get(), type.get(), buffer.data()), where,
        "read attribute " + single_quoted(attribute_name) + " of", object);
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

}  // namespace ggk::engine
