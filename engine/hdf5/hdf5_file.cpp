#include "engine/hdf5/hdf5_file.hpp"

#include <hdf5.h>

#include <chrono>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>

#include "engine/hdf5/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of this file's parts

// The header keeps hdf5.h out of its includers and stores the file id as int64.
static_assert(std::is_same_v<hid_t, std::int64_t>, "HDF5 >= 1.10 uses 64-bit hid_t");

namespace fs = std::filesystem;

namespace {

// HDF5 closes every file still open when the process exits (H5_term_library,
// registered with atexit). After a failed H5Fclose (a full disk, /dev/null)
// that second close reads freed memory and crashes, turning a reported error
// into a SIGSEGV. Every file here is closed by its owner, so the exit hook is
// switched off before the library initialises (a static initialiser of the
// one file every user of Hdf5File links).
[[maybe_unused]] const bool kNoHdf5ExitHook = [] {
  H5dont_atexit();
  return true;
}();

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
  if (error && error != std::errc::no_such_file_or_directory) {
    return " (" + error.message() + ")";  // a symbolic link loop, a folder not searchable
  }
  if (!fs::exists(status)) {
    return fs::is_symlink(fs::symlink_status(path, error)) ? " (a symbolic link to no file)"
                                                           : " (no such file)";
  }
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
      problem = " (no such directory " + single_quoted(path.parent_path().string()) + ")";
    }
    throw std::runtime_error("cannot create HDF5 file " + single_quoted(path.string()) + problem +
                             ": " + reason);
  }
  return Hdf5File(path, id, false);
}

namespace {

// A reader's metadata cache: HDF5's default bound (32 MiB, counted in on-disk
// bytes) holds B-tree nodes and object headers whose in-memory form is ~10x
// larger: `ggk verify` of a 158 MB file peaked at 390 MB of RSS, 72 MB with
// this bound, in the same time (8.4 vs 8.8 s, then 10.6 vs 9.9 s, results/
// acrobot.h5). A reader walks a file once; a writer keeps the default.
constexpr std::size_t kReaderMetadataCacheBytes = std::size_t{4} << 20;

Handle reader_access_list(const Context& where) {
  Handle fapl = make_property_list(H5P_FILE_ACCESS, where, "/");
  H5AC_cache_config_t config;
  config.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  check(H5Pget_mdc_config(fapl.get(), &config), where, "read the metadata cache settings of", "/");
  config.set_initial_size = true;
  config.initial_size = kReaderMetadataCacheBytes / 2;
  config.min_size = kReaderMetadataCacheBytes / 4;
  config.max_size = kReaderMetadataCacheBytes;
  check(H5Pset_mdc_config(fapl.get(), &config), where, "bound the metadata cache of", "/");
  return fapl;
}

}  // namespace

Hdf5File Hdf5File::open(const std::filesystem::path& path, bool read_only) {
  disable_automatic_error_printing();
  std::optional<Handle> fapl;
  if (read_only) fapl.emplace(reader_access_list(Context{H5I_INVALID_HID, path}));
  const hid_t id = H5Fopen(path.c_str(), read_only ? H5F_ACC_RDONLY : H5F_ACC_RDWR,
                           fapl ? fapl->get() : H5P_DEFAULT);
  if (id < 0) {
    const std::string reason = take_hdf5_reason();
    throw std::runtime_error("cannot open HDF5 file " + single_quoted(path.string()) +
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

namespace {

bool is_lock_conflict(const std::string& message) {
  return message.find("unable to lock file") != std::string::npos;
}

}  // namespace

Hdf5File Hdf5File::open_waiting_for_lock(const std::filesystem::path& path, bool read_only,
                                         std::chrono::milliseconds patience) {
  const auto give_up = std::chrono::steady_clock::now() + patience;
  for (;;) {
    try {
      return open(path, read_only);
    } catch (const std::runtime_error& e) {
      if (!is_lock_conflict(e.what()) || std::chrono::steady_clock::now() >= give_up) throw;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

Hdf5File Hdf5File::reopen_for_writer(const std::filesystem::path& path) {
  try {
    return open_waiting_for_lock(path, false, std::chrono::seconds(3));
  } catch (const std::runtime_error& e) {
    if (!is_lock_conflict(e.what())) throw;
  }
  // A reader keeps the file open (a notebook): write without HDF5's lock. The
  // caller holds ggk's own output lock, so no second writer can be there.
  const Context where{-1, path};
  const Handle fapl = make_property_list(H5P_FILE_ACCESS, where, "/");
  check(H5Pset_file_locking(fapl.get(), false, true), where, "switch off file locking for", "/");
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get());
  if (id < 0) {
    throw std::runtime_error("cannot open HDF5 file " + single_quoted(path.string()) +
                             file_problem(path) + ": " + take_hdf5_reason());
  }
  return Hdf5File(path, id, false);
}

void Hdf5File::close() {
  if (id_ < 0) return;
  disable_automatic_error_printing();
  const hid_t id = std::exchange(id_, -1);
  if (H5Fclose(id) < 0) throw_hdf5_error(path_, "close", "/");
}

void Hdf5File::renamed_to(const std::filesystem::path& path) {
  path_ = path;
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
                      "parent " + single_quoted(lookup.blocking_parent) + " is not a group");
  }
}

std::string Hdf5File::new_object_path(std::string_view path) const {
  std::string name = normalized(path, path_);
  require_new_object(name);
  return name;
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
        "move " + single_quoted(source) + " to", target);
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

}  // namespace ggk::engine
