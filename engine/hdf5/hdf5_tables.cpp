#include "engine/hdf5/hdf5_file.hpp"

#include <hdf5.h>

#include <cstring>
#include <type_traits>
#include <utility>

#include "engine/hdf5/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of this file's parts

namespace {

namespace fs = std::filesystem;

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
      return column.string_size == 0 ? sizeof(char*) : column.string_size;
  }
  return 0;
}

bool is_variable(const TableColumn& column) {
  return column.type == ColumnType::kString && column.string_size == 0;
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
    for (std::size_t j = 0; j < i; ++j) {
      if (columns[j].name == column.name) {
        throw_store_error(where.file_path, path, "duplicate column " + single_quoted(column.name));
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
        const Handle string_type = is_variable(column)
                                       ? variable_string_type(where, path)
                                       : fixed_string_type(where, column.string_size, path);
        status = H5Tinsert(compound.get(), column.name.c_str(), offsets[i], string_type.get());
        break;
      }
    }
    check(status, where, "add column " + single_quoted(column.name) + " to", path);
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
    } else if (H5Tget_class(member.get()) == H5T_STRING) {
      // Variable-length (string_size 0, what the engine writes) or fixed-length
      // (files of ggk before the variable-length tables).
      column.type = ColumnType::kString;
      column.string_size = H5Tis_variable_str(member.get()) > 0 ? 0 : H5Tget_size(member.get());
    } else {
      throw_store_error(where.file_path, path,
                        "column " + single_quoted(column.name) + " has unsupported type " +
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
            "row " + std::to_string(r) + ", column " + single_quoted(column.name) + ": " + problem);
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
          if (is_variable(column)) {
            // The cell points into the row, which outlives the write.
            if (text.find('\0') != std::string::npos) wrong("string contains a NUL character");
            const char* pointer = text.c_str();
            std::memcpy(cell, &pointer, sizeof pointer);
            break;
          }
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
  // A checksum but no compression. Appending to a filtered chunk rewrites the
  // whole chunk, and a kill in the middle could destroy rows already flushed;
  // the engine therefore writes each table whole under a staging path
  // (run_store.hpp) and never appends to a committed one. The checksum keeps
  // the chunk's size, so a rewrite stays in place.
  check(H5Pset_chunk(dcpl.get(), 1, chunk), where, "set chunks of", name);
  check(H5Pset_fletcher32(dcpl.get()), where, "set the checksum filter of", name);
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
  const Handle memory_type = row_type(where, name, columns, false);
  if (count > 0) {
    check(H5Dread(dataset.get(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()),
          where, "read table", name);
  }
  // HDF5 allocated the variable-length strings: copied out below, then freed.
  struct Reclaim {
    hid_t type, space;
    void* data;
    std::size_t count;
    ~Reclaim() {
      if (count > 0) H5Dvlen_reclaim(type, space, H5P_DEFAULT, data);
    }
  } reclaim{memory_type.get(), space.get(), buffer.data(), count};
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
          if (is_variable(columns[c])) {
            const char* text = nullptr;
            std::memcpy(&text, cell, sizeof text);
            rows[r].emplace_back(std::string(text == nullptr ? "" : text));
          } else {
            rows[r].emplace_back(decode_fixed_string(reinterpret_cast<const char*>(cell),
                                                     columns[c].string_size, H5T_STR_NULLPAD));
          }
          break;
      }
    }
  }
  return rows;
}

}  // namespace ggk::engine
