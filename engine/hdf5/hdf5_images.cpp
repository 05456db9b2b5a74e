// Hdf5File: in-memory files (HDF5's core driver) and copying objects between
// files, which together move a run's group from one MPI rank to another.

#include <hdf5.h>

#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/hdf5/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of Hdf5File's parts

namespace {

// A file access property list for the core driver without a backing file.
Handle in_memory_access(const std::filesystem::path& name) {
  const Context where{H5I_INVALID_HID, name};
  Handle access = make_property_list(H5P_FILE_ACCESS, where, "/");
  // Grow the image in 1 MiB steps; never write it to disk.
  check(H5Pset_fapl_core(access.get(), 1 << 20, false), where, "set the core driver for", "/");
  return access;
}

}  // namespace

Hdf5File Hdf5File::create_in_memory(const std::string& name) {
  disable_automatic_error_printing();
  const Handle access = in_memory_access(std::filesystem::path(name));
  const hid_t id = H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get());
  if (id < 0) {
    throw std::runtime_error("cannot create in-memory HDF5 file " + single_quoted(name) + ": " +
                             take_hdf5_reason());
  }
  return Hdf5File(name, id, false);
}

bool Hdf5File::in_memory() const {
  disable_automatic_error_printing();
  const Context where{id_, path_};
  const Handle access =
      checked(H5Fget_access_plist(id_), H5Pclose, where, "get the access of", "/");
  return H5Pget_driver(access.get()) == H5FD_CORE;
}

std::vector<unsigned char> Hdf5File::file_image() {
  flush();
  const Context where{id_, path_};
  const ssize_t size = H5Fget_file_image(id_, nullptr, 0);
  if (size < 0) throw_hdf5_error(path_, "measure the image of", "/");
  std::vector<unsigned char> image(static_cast<std::size_t>(size));
  if (H5Fget_file_image(id_, image.data(), image.size()) != size) {
    throw_hdf5_error(path_, "copy the image of", "/");
  }
  return image;
}

Hdf5File Hdf5File::open_image(std::span<const unsigned char> image, const std::string& name) {
  disable_automatic_error_printing();
  const std::filesystem::path file_name(name);
  const Handle access = in_memory_access(file_name);
  const Context where{H5I_INVALID_HID, file_name};
  // HDF5 copies the buffer: the image need not outlive the file.
  check(H5Pset_file_image(access.get(), const_cast<unsigned char*>(image.data()), image.size()),
        where, "hand over the image of", "/");
  const hid_t id = H5Fopen(name.c_str(), H5F_ACC_RDONLY, access.get());
  if (id < 0) {
    throw std::runtime_error("cannot open HDF5 image " + single_quoted(name) + " (" +
                             std::to_string(image.size()) + " bytes): " + take_hdf5_reason());
  }
  return Hdf5File(name, id, true);
}

void Hdf5File::copy_from(const Hdf5File& source, std::string_view source_path,
                         std::string_view destination_path) {
  const std::string from = normalized(source_path, source.path_);
  const std::string to = normalized(destination_path, path_);
  require_existing(Context{source.id_, source.path_}, from);
  require_new_object(to);
  const Context where{id_, path_};
  const Handle create_parents = intermediate_groups_lcpl(where, to);
  check(H5Ocopy(source.id_, from.c_str(), id_, to.c_str(), H5P_DEFAULT, create_parents.get()),
        where, "copy " + single_quoted(source.path_.string() + ":" + from) + " to", to);
}

}  // namespace ggk::engine
