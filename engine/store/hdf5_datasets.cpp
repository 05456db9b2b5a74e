#include "engine/store/hdf5_file.hpp"

#include <hdf5.h>

#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>

#include "engine/store/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of this file's parts

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

}  // namespace ggk::engine
