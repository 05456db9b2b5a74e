#include "engine/store/disk_room.hpp"

#include <sys/resource.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <system_error>

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

std::string megabytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", static_cast<double>(bytes) / 1e6);
  return text;
}

}  // namespace

std::uint64_t room_for(const fs::path& file) {
  std::uint64_t room = UINT64_MAX;
  const fs::path directory = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  struct statvfs status {};
  if (::statvfs(directory.c_str(), &status) == 0) {
    room = static_cast<std::uint64_t>(status.f_bavail) * status.f_frsize;
  }
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    std::error_code error;
    const std::uintmax_t size = fs::file_size(file, error);
    const std::uint64_t used = error ? 0 : size;
    const std::uint64_t allowed = limit.rlim_cur > used ? limit.rlim_cur - used : 0;
    room = std::min(room, allowed);
  }
  return room;
}

void require_room(const fs::path& file, std::uint64_t bytes, const std::string& what) {
  const std::uint64_t room = room_for(file);
  if (bytes <= room) return;
  throw std::runtime_error("no room to write " + what + " to " + file.string() +
                           ": it needs up to " + megabytes(bytes) + ", and " + megabytes(room) +
                           " are left (free space on the file system, or the file size limit); "
                           "nothing of it was written");
}

}  // namespace ggk::engine
