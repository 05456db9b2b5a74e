// Hdf5File: walking a file (kinds, member and attribute names) and reading any
// dataset or attribute into a canonical form (Hdf5File::Values), for tools that
// compare or join whole files (ggk diff, ggk merge), by path or through an
// object held open (Hdf5File::Object, for walks over a whole tree).

#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/hdf5/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of Hdf5File's parts

namespace {

// Reads a dataset's or an attribute's elements in a memory type.
using ReadAs = std::function<void(hid_t memory_type, void* buffer)>;

// Appends the elements of one (non-compound) type: numbers as native bytes,
// strings decoded. `file_type` is the stored type; `count` the element count.
void append_values(const Context& where, const std::string& path, const std::string& member,
                   hid_t file_type, std::size_t count, const ReadAs& read,
                   Hdf5File::Values& values) {
  const H5T_class_t type_class = H5Tget_class(file_type);
  if (type_class == H5T_STRING) {
    values.parts.push_back({member, Hdf5File::ElementClass::kString, 0});
    if (H5Tis_variable_str(file_type) > 0) {
      const Handle memory = variable_string_type(where, path);
      std::vector<char*> pointers(count, nullptr);
      read(memory.get(), pointers.data());
      for (char* text : pointers) {
        values.strings.emplace_back(text == nullptr ? "" : text);
        H5free_memory(text);
      }
    } else {
      const std::size_t size = H5Tget_size(file_type);
      const Handle memory = fixed_string_type(where, size, path);
      std::vector<char> bytes(count * size);
      read(memory.get(), bytes.data());
      const H5T_str_t padding = H5Tget_strpad(file_type);
      for (std::size_t i = 0; i < count; ++i) {
        values.strings.push_back(decode_fixed_string(bytes.data() + i * size, size, padding));
      }
    }
    values.type += "string";
    return;
  }
  const Handle memory = checked(H5Tget_native_type(file_type, H5T_DIR_ASCEND), H5Tclose, where,
                                "get the native type of", path);
  const std::size_t size = H5Tget_size(memory.get());
  const std::size_t offset = values.bytes.size();
  values.bytes.resize(offset + count * size);
  read(memory.get(), values.bytes.data() + offset);
  values.type += describe_type(file_type);
  Hdf5File::ElementClass element_class = Hdf5File::ElementClass::kOther;
  if (type_class == H5T_FLOAT) {
    element_class = Hdf5File::ElementClass::kFloat;
  } else if (type_class == H5T_INTEGER) {
    element_class = H5Tget_sign(file_type) == H5T_SGN_NONE ? Hdf5File::ElementClass::kUnsigned
                                                           : Hdf5File::ElementClass::kSigned;
  }
  values.parts.push_back({member, element_class, size});
}

// The whole canonical form of one dataset or attribute of type `file_type` with
// `count` elements; a compound is read member by member (minus `skip`).
void read_canonical(const Context& where, const std::string& path, hid_t file_type,
                    std::size_t count, const std::function<void(hid_t, void*)>& read,
                    std::span<const std::string> skip, Hdf5File::Values& values) {
  if (H5Tget_class(file_type) != H5T_COMPOUND) {
    append_values(where, path, "", file_type, count, read, values);
    return;
  }
  values.type += "{";
  const int members = H5Tget_nmembers(file_type);
  for (int m = 0; m < members; ++m) {
    char* raw_name = H5Tget_member_name(file_type, static_cast<unsigned>(m));
    const std::string name = raw_name == nullptr ? "" : raw_name;
    H5free_memory(raw_name);
    if (std::find(skip.begin(), skip.end(), name) != skip.end()) continue;
    const Handle member = checked(H5Tget_member_type(file_type, static_cast<unsigned>(m)), H5Tclose,
                                  where, "get a member type of", path);
    values.type += name + ":";
    // Read this member alone, through a one-member compound of its memory type.
    const ReadAs read_member = [&](hid_t memory_type, void* buffer) {
      const Handle single = checked(H5Tcreate(H5T_COMPOUND, H5Tget_size(memory_type)), H5Tclose,
                                    where, "create a member type for", path);
      check(H5Tinsert(single.get(), name.c_str(), 0, memory_type), where,
            "set up member " + single_quoted(name) + " of", path);
      read(single.get(), buffer);
    };
    append_values(where, path, name, member.get(), count, read_member, values);
    values.type += ";";
  }
  values.type += "}";
}

std::vector<std::int64_t> shape_of(const Context& where, const Handle& space,
                                   const std::string& path, std::size_t& count) {
  const std::vector<hsize_t> dims = space_dims(where, space, path);
  count = element_count(dims);
  return std::vector<std::int64_t>(dims.begin(), dims.end());
}

herr_t collect_link_name(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

herr_t collect_attribute_name(hid_t, const char* name, const H5A_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

// The canonical form of an open dataset's values (Hdf5File::read_values).
Hdf5File::Values dataset_values(const Context& where, hid_t dataset, const std::string& name,
                                std::span<const std::string> skip_members) {
  const Handle type = checked(H5Dget_type(dataset), H5Tclose, where, "get the type of", name);
  const Handle space = checked(H5Dget_space(dataset), H5Sclose, where, "get the shape of", name);
  Hdf5File::Values values;
  std::size_t count = 0;
  values.shape = shape_of(where, space, name, count);
  if (count == 0) {
    values.type = describe_type(type.get());
    return values;
  }
  // A damaged header can claim any size: what the dataset stores bounds what
  // it holds (deflate packs at most 1032:1), so an impossible claim is an error
  // here, not an allocation of terabytes.
  const double claimed = static_cast<double>(count) * static_cast<double>(H5Tget_size(type.get()));
  const double stored = static_cast<double>(H5Dget_storage_size(dataset));
  if (claimed > 1100.0 * stored + 1048576.0) {
    throw_store_error(where.file_path, name,
                      "claims " + std::to_string(count) + " elements (" +
                          std::to_string(static_cast<long long>(claimed)) + " bytes) but stores " +
                          std::to_string(static_cast<long long>(stored)) +
                          " bytes: its shape or type is damaged");
  }
  read_canonical(
      where, name, type.get(), count,
      [&](hid_t memory_type, void* buffer) {
        check(H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer), where,
              "read dataset", name);
      },
      skip_members, values);
  return values;
}

// The canonical form of an open attribute's values (Hdf5File::read_attribute_values);
// `object` and `name` name it in errors.
Hdf5File::Values attribute_values(const Context& where, hid_t attribute, const std::string& object,
                                  const std::string& name) {
  const Handle type = checked(H5Aget_type(attribute), H5Tclose, where,
                              "get the type of attribute " + single_quoted(name) + " of", object);
  const Handle space =
      checked(H5Aget_space(attribute), H5Sclose, where,
              "get the dataspace of attribute " + single_quoted(name) + " of", object);
  Hdf5File::Values values;
  std::size_t count = 0;
  values.shape = shape_of(where, space, object, count);
  if (count == 0) {
    values.type = describe_type(type.get());
    return values;
  }
  // An attribute's values are stored in the file (its object header, or the
  // dense attribute storage), so they fit in it: a damaged shape is an error
  // here, not an allocation of gigabytes.
  const double claimed = static_cast<double>(count) * static_cast<double>(H5Tget_size(type.get()));
  hsize_t file_size = 0;
  if (H5Fget_filesize(where.file, &file_size) >= 0 && claimed > static_cast<double>(file_size)) {
    throw_store_error(where.file_path, object,
                      "attribute " + single_quoted(name) + " claims " + std::to_string(count) +
                          " elements (" + std::to_string(static_cast<long long>(claimed)) +
                          " bytes), more than the whole file holds: its shape or type is damaged");
  }
  read_canonical(
      where, object, type.get(), count,
      [&](hid_t memory_type, void* buffer) {
        check(H5Aread(attribute, memory_type, buffer), where,
              "read attribute " + single_quoted(name) + " of", object);
      },
      {}, values);
  return values;
}

Hdf5File::ObjectKind kind_of(hid_t object) {
  switch (H5Iget_type(object)) {
    case H5I_GROUP:
      return Hdf5File::ObjectKind::kGroup;
    case H5I_DATASET:
      return Hdf5File::ObjectKind::kDataset;
    default:
      return Hdf5File::ObjectKind::kOther;
  }
}

std::vector<std::string> sorted_members(const Context& where, hid_t group,
                                        const std::string& name) {
  std::vector<std::string> names;
  hsize_t index = 0;
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, &index, collect_link_name, &names), where,
        "list the members of", name);
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> sorted_attributes(const Context& where, hid_t object,
                                           const std::string& name) {
  std::vector<std::string> names;
  hsize_t index = 0;
  check(H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, &index, collect_attribute_name, &names),
        where, "list the attributes of", name);
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

Hdf5File::ObjectKind Hdf5File::object_kind(std::string_view path) const {
  const std::string name = normalized(path, path_);
  const Context where{id_, path_};
  require_existing(where, name);
  const Handle object =
      checked(H5Oopen(id_, name.c_str(), H5P_DEFAULT), H5Oclose, where, "open", name);
  return kind_of(object.get());
}

std::optional<std::uint64_t> Hdf5File::hard_link_address(std::string_view path) const {
  const std::string name = normalized(path, path_);
  const Context where{id_, path_};
  if (name != "/") {
    H5L_info_t link{};
    check(H5Lget_info(id_, name.c_str(), &link, H5P_DEFAULT), where, "read the link", name);
    if (link.type != H5L_TYPE_HARD) return std::nullopt;
  }
  H5O_info_t info{};
  check(H5Oget_info_by_name2(id_, name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT), where,
        "read the object header of", name);
  return static_cast<std::uint64_t>(info.addr);
}

std::vector<std::string> Hdf5File::member_names(std::string_view group_path) const {
  const std::string name = normalized(group_path, path_);
  const Context where{id_, path_};
  require_existing(where, name);
  const Handle group =
      checked(H5Gopen2(id_, name.c_str(), H5P_DEFAULT), H5Gclose, where, "open group", name);
  return sorted_members(where, group.get(), name);
}

std::vector<std::string> Hdf5File::attribute_names(std::string_view object_path) const {
  const std::string name = normalized(object_path, path_);
  const Context where{id_, path_};
  require_existing(where, name);
  const Handle object =
      checked(H5Oopen(id_, name.c_str(), H5P_DEFAULT), H5Oclose, where, "open", name);
  return sorted_attributes(where, object.get(), name);
}

Hdf5File::Values Hdf5File::read_values(std::string_view dataset_path,
                                       std::span<const std::string> skip_members) const {
  const std::string name = normalized(dataset_path, path_);
  const Context where{id_, path_};
  require_existing(where, name);
  const Handle dataset = open_dataset(where, name);
  return dataset_values(where, dataset.get(), name, skip_members);
}

Hdf5File::Values Hdf5File::read_attribute_values(std::string_view object_path,
                                                 std::string_view attribute_name) const {
  const std::string object = normalized(object_path, path_);
  const std::string attribute_name_text(attribute_name);
  const Context where{id_, path_};
  require_existing(where, object);
  const Handle attribute = checked(
      H5Aopen_by_name(id_, object.c_str(), attribute_name_text.c_str(), H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose, where, "open attribute " + single_quoted(attribute_name_text) + " of", object);
  return attribute_values(where, attribute.get(), object, attribute_name_text);
}

// ---------------------------------------------------------------- Object

Hdf5File::Object::Object(const Hdf5File& file, std::string path, std::int64_t id)
    : file_(&file), path_(std::move(path)), id_(id) {}

Hdf5File::Object::Object(Object&& other) noexcept
    : file_(other.file_), path_(std::move(other.path_)), id_(std::exchange(other.id_, -1)) {}

Hdf5File::Object::~Object() {
  if (id_ >= 0) H5Oclose(id_);
}

std::optional<Hdf5File::Object> Hdf5File::open_hard_link(std::string_view path) const {
  const std::string name = normalized(path, path_);
  const Context where{id_, path_};
  if (name != "/") {
    require_existing(where, name);
    H5L_info_t link{};
    check(H5Lget_info(id_, name.c_str(), &link, H5P_DEFAULT), where, "read the link", name);
    if (link.type != H5L_TYPE_HARD) return std::nullopt;
  }
  const hid_t id = H5Oopen(id_, name.c_str(), H5P_DEFAULT);
  if (id < 0) throw_hdf5_error(path_, "open", name);
  return Object(*this, name, id);
}

Hdf5File::ObjectKind Hdf5File::Object::kind() const {
  return kind_of(id_);
}

std::vector<std::string> Hdf5File::Object::member_names() const {
  return sorted_members(Context{file_->id_, file_->path_}, id_, path_);
}

std::optional<Hdf5File::Object> Hdf5File::Object::hard_member(std::string_view name) const {
  const Context where{file_->id_, file_->path_};
  const std::string text(name);
  const std::string member = join(path_, name);
  H5L_info_t link{};
  check(H5Lget_info(id_, text.c_str(), &link, H5P_DEFAULT), where, "read the link", member);
  if (link.type != H5L_TYPE_HARD) return std::nullopt;
  const hid_t id = H5Oopen(id_, text.c_str(), H5P_DEFAULT);
  if (id < 0) throw_hdf5_error(file_->path_, "open", member);
  return Object(*file_, member, id);
}

std::vector<std::string> Hdf5File::Object::attribute_names() const {
  return sorted_attributes(Context{file_->id_, file_->path_}, id_, path_);
}

Hdf5File::Values Hdf5File::Object::read_attribute_values(std::string_view name) const {
  const Context where{file_->id_, file_->path_};
  const std::string text(name);
  const Handle attribute = checked(H5Aopen(id_, text.c_str(), H5P_DEFAULT), H5Aclose, where,
                                   "open attribute " + single_quoted(text) + " of", path_);
  return attribute_values(where, attribute.get(), path_, text);
}

std::vector<std::int64_t> Hdf5File::Object::dataset_shape() const {
  const Context where{file_->id_, file_->path_};
  const Handle space = checked(H5Dget_space(id_), H5Sclose, where, "get the shape of", path_);
  std::size_t count = 0;
  return shape_of(where, space, path_, count);
}

Hdf5File::Values Hdf5File::Object::read_values(std::span<const std::string> skip_members) const {
  return dataset_values(Context{file_->id_, file_->path_}, id_, path_, skip_members);
}

void Hdf5File::Object::write_string_attribute(std::string_view name, std::string_view value) {
  const Context where{file_->id_, file_->path_};
  if (file_->read_only_) throw_store_error(file_->path_, path_, "file is open read-only");
  const std::string text_name(name);
  const htri_t found = H5Aexists(id_, text_name.c_str());
  if (found < 0) {
    throw_hdf5_error(file_->path_, "look up attribute " + single_quoted(name) + " of", path_);
  }
  if (found > 0) {
    throw_store_error(file_->path_, path_, "attribute " + single_quoted(name) + " already exists");
  }
  require_no_nul(where, path_, value);
  const std::string text(value);
  const char* pointer = text.c_str();
  const Handle type = variable_string_type(where, path_);
  const Handle space =
      checked(H5Screate(H5S_SCALAR), H5Sclose, where, "create dataspace for", path_);
  const Handle attribute =
      checked(H5Acreate2(id_, text_name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, where, "create attribute " + single_quoted(name) + " of", path_);
  check(H5Awrite(attribute.get(), type.get(), &pointer), where,
        "write attribute " + single_quoted(name) + " of", path_);
}

}  // namespace ggk::engine
