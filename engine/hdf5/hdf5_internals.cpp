#include "engine/hdf5/hdf5_internals.hpp"

#include <hdf5.h>

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <new>
#include <optional>
#include <stdexcept>

#include "engine/hdf5/allocation_failures.hpp"

namespace ggk::engine {

namespace {
std::atomic<AllocationFailure> g_allocation_failures{AllocationFailure::kOutOfMemory};
}  // namespace

void set_allocation_failures(AllocationFailure meaning) {
  g_allocation_failures = meaning;
}

AllocationFailure allocation_failures() {
  return g_allocation_failures;
}

}  // namespace ggk::engine

namespace ggk::engine::hdf5_internals {

namespace {

herr_t collect_error_description(unsigned /*depth*/, const H5E_error2_t* error, void* data) {
  auto& descriptions = *static_cast<std::vector<std::string>*>(data);
  if (error->desc != nullptr && error->desc[0] != '\0' &&
      (descriptions.empty() || descriptions.back() != error->desc)) {
    descriptions.emplace_back(error->desc);
  }
  return 0;
}

// HDF5's file drivers describe a failed system call with everything they know
// ("file write failed: time = ..., filename = '<the name the file was opened
// under>', file descriptor = 3, errno = 28, error message = 'No space left on
// device', buf = 0x..., total write size = ..."): the name may be one the file
// no longer has (a .part renamed into place) and the rest is noise to a user.
// Such a description becomes "file write failed: No space left on device"; an
// open's ("unable to open file: name = '...', errno = 40, error message = '...',
// flags = 0, o_flags = 0") likewise.
std::string plain_system_error(const std::string& description) {
  const std::string marker = "error message = '";
  const std::size_t message = description.find(marker);
  const std::size_t fields = std::min(description.find(": time = "), description.find(": name = "));
  if (message == std::string::npos || fields == std::string::npos) return description;
  const std::size_t start = message + marker.size();
  const std::size_t end = description.find('\'', start);
  if (end == std::string::npos) return description;
  return description.substr(0, fields) + ": " + description.substr(start, end - start);
}

std::string file_prefix(const fs::path& file) {
  return "HDF5 file " + single_quoted(file.string());
}

}  // namespace

// ---------------------------------------------------------------- errors

void disable_automatic_error_printing() {
  thread_local bool disabled = false;
  if (!disabled) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    disabled = true;
  }
}

namespace {

bool contains(const std::string& text, std::string_view part) {
  return text.find(part) != std::string::npos;
}

// A description of a failed memory allocation (allocation_failures.hpp); not
// "unable to allocate file memory", which is space in the file.
bool is_allocation_failure(const std::string& description) {
  if (contains(description, "memory allocation failed") ||
      contains(description, "memory reallocation failed") ||
      contains(description, "unable to allocate memory")) {
    return true;
  }
  if (!contains(description, "inflate() failed") &&
      !contains(description, "inflateInit() failed")) {
    return false;
  }
  rlimit limit{};
  return ::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY;
}

}  // namespace

std::string take_hdf5_reason() {
  std::vector<std::string> descriptions;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect_error_description, &descriptions);
  H5Eclear2(H5E_DEFAULT);
  const bool allocation =
      std::any_of(descriptions.begin(), descriptions.end(),
                  [](const std::string& d) { return is_allocation_failure(d); });
  if (allocation) {
    if (allocation_failures() == AllocationFailure::kOutOfMemory) throw std::bad_alloc();
    descriptions.emplace_back(
        "an allocation failed within the room ggk allows for reading this file: a size in it "
        "is damaged");
  }
  if (descriptions.empty()) return "HDF5 gave no reason";
  std::string reason = descriptions.front();
  if (descriptions.size() > 1) {
    const std::string innermost = plain_system_error(descriptions.back());
    reason = innermost.starts_with(reason + ":") ? innermost : reason + ": " + innermost;
  }
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  return reason;
}

[[noreturn]] void throw_hdf5_error(const fs::path& file, std::string_view what,
                                   std::string_view object_path) {
  throw std::runtime_error(file_prefix(file) + ": cannot " + std::string(what) + " " +
                           single_quoted(object_path) + ": " + take_hdf5_reason());
}

[[noreturn]] void throw_store_error(const fs::path& file, std::string_view object_path,
                                    std::string_view problem) {
  throw std::runtime_error(file_prefix(file) + ": " + single_quoted(object_path) + ": " +
                           std::string(problem));
}

// ---------------------------------------------------------------- handles

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

std::string normalized(std::string_view path, const fs::path& file) {
  if (path.empty()) throw_store_error(file, path, "empty object path");
  std::string result = path.front() == '/' ? std::string(path) : "/" + std::string(path);
  while (result.size() > 1 && result.back() == '/') result.pop_back();
  return result;
}

std::string join(const std::string& parent, std::string_view child) {
  return parent == "/" ? parent + std::string(child) : parent + "/" + std::string(child);
}

Lookup look_up(const Context& where, const std::string& path) {
  if (path == "/") return {true, ""};
  // H5Lexists only looks at the last component and fails when a parent is
  // missing, so walk the path one component at a time; every parent must be a
  // group. Each component is looked up in its parent, held open, so a path of L
  // components costs L lookups, not the L^2 / 2 of looking up every prefix from
  // the root.
  std::optional<Handle> parent;  // the group walked so far; none: the root (where.file)
  std::size_t end = 0;
  while (end != std::string::npos) {
    const std::size_t begin = end + 1;
    end = path.find('/', begin);
    if (end == begin) continue;  // "//" in the path
    const std::string component = path.substr(begin, end == std::string::npos ? end : end - begin);
    const hid_t within = parent ? parent->get() : where.file;
    const htri_t found = H5Lexists(within, component.c_str(), H5P_DEFAULT);
    if (found < 0) throw_hdf5_error(where.file_path, "look up", path.substr(0, end));
    if (found == 0) return {false, ""};
    if (end != std::string::npos) {
      const std::string prefix = path.substr(0, end);
      Handle object =
          checked(H5Oopen(within, component.c_str(), H5P_DEFAULT), H5Oclose, where, "open", prefix);
      if (H5Iget_type(object.get()) != H5I_GROUP) return {false, prefix};
      parent.emplace(std::move(object));
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

Handle variable_string_type(const Context& where, std::string_view object_path) {
  Handle type = checked(H5Tcopy(H5T_C_S1), H5Tclose, where, "make string type for", object_path);
  check(H5Tset_size(type.get(), H5T_VARIABLE), where, "make string type for", object_path);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "make string type for", object_path);
  return type;
}

Handle fixed_string_type(const Context& where, std::size_t size, std::string_view object_path) {
  Handle type = checked(H5Tcopy(H5T_C_S1), H5Tclose, where, "make string type for", object_path);
  check(H5Tset_size(type.get(), size), where, "make string type for", object_path);
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), where, "make string type for", object_path);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), where, "make string type for", object_path);
  return type;
}

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

}  // namespace ggk::engine::hdf5_internals
