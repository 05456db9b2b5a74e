#pragma once
// Room on disk before a commit. HDF5 writes a flush's metadata in pieces: when
// the disk fills up in the middle, the pieces that landed can point to pieces
// that did not, and the file's scratch space, or worse, no longer reads. So the
// writer makes sure, before it starts a commit (a run, the summary), that the
// file system has room for everything the commit can write, and stops cleanly
// (the file as its last commit left it) when it has not. Another process filling
// the disk during the commit is not covered: --resume then repairs what it can.

#include <cstdint>
#include <filesystem>
#include <string>

namespace ggk::engine {

// Throws std::runtime_error naming `what`, the bytes needed and the room left
// when the file system holding `file` (or the process's file size limit,
// RLIMIT_FSIZE) has less than `bytes` of room for `file` to grow.
void require_room(const std::filesystem::path& file, std::uint64_t bytes, const std::string& what);

// The room left for `file` to grow: free bytes on its file system for this user,
// and no more than the file size limit allows.
std::uint64_t room_for(const std::filesystem::path& file);

}  // namespace ggk::engine
