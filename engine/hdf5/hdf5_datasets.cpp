#include "engine/hdf5/hdf5_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <limits>

#include "engine/hdf5/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of this file's parts

namespace {

// Chunks of about this many bytes: large enough for gzip to work well, small
// enough that reading one value does not inflate megabytes.
constexpr std::size_t kTargetChunkBytes = 256 * 1024;

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

// Dataset creation properties: chunked, shuffle + gzip + Fletcher32, unless the dataset is
// empty (contiguous: there is nothing to compress and no chunk would fit).
Handle compressed_dcpl(const Context& where, std::span<const hsize_t> dims,
                       std::size_t element_size, int gzip_level, bool checksum,
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
  // Last in the pipeline: the checksum covers the bytes on disk.
  if (checksum) {
    check(H5Pset_fletcher32(dcpl.get()), where, "set the checksum filter of", object_path);
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
  // Variable-length data (strings) lives in a heap that no filter reaches: a
  // checksum of the chunk's heap pointers would not cover it (HDF5 refuses it).
  const bool fixed_size = H5Tis_variable_str(file_type) <= 0;
  const Handle dcpl = compressed_dcpl(where, dims, element_size, gzip_level, fixed_size, path);
  const Handle lcpl = intermediate_groups_lcpl(where, path);
  const Handle dataset = checked(H5Dcreate2(where.file, path.c_str(), file_type, space.get(),
                                            lcpl.get(), dcpl.get(), H5P_DEFAULT),
                                 H5Dclose, where, "create dataset", path);
  if (element_count(dims) == 0) return;
  check(H5Dwrite(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), where,
        "write dataset", path);
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

}  // namespace

// ---------------------------------------------------------------- numeric

void Hdf5File::write_vector(std::string_view path, std::span<const double> values) {
  write_vector_of(Context{id_, path_}, new_object_path(path), values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const float> values) {
  write_vector_of(Context{id_, path_}, new_object_path(path), values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const std::int32_t> values) {
  write_vector_of(Context{id_, path_}, new_object_path(path), values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const std::int64_t> values) {
  write_vector_of(Context{id_, path_}, new_object_path(path), values, gzip_level_);
}

void Hdf5File::write_vector(std::string_view path, std::span<const std::uint8_t> values) {
  write_vector_of(Context{id_, path_}, new_object_path(path), values, gzip_level_);
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
  write_matrix_of(Context{id_, path_}, new_object_path(path), rows, cols, values, gzip_level_);
}

void Hdf5File::write_matrix(std::string_view path, std::int64_t rows, std::int64_t cols,
                            std::span<const std::int32_t> values) {
  write_matrix_of(Context{id_, path_}, new_object_path(path), rows, cols, values, gzip_level_);
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
