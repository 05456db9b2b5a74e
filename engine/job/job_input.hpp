#pragma once
// A file a job file names (the maze's map_file, the Khepera's arena_file), read
// whole when the job is loaded. Its text is stored with the results (root
// attribute "input:<key>", engine/store/results_layout.hpp) and `ggk run --resume` refuses a
// results file whose inputs differ from the files now on disk, as it refuses another job file.
//
// Job files and the files they name are read through read_regular_file(): only
// regular files (symlinks followed), at most kMaxInputFileBytes, and never a read
// that can block (a FIFO, a device) or run until memory runs out (/dev/zero).

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace ggk::engine {

class TomlTableReader;

// The most bytes a job file or a file it names may hold: 16 MiB, far more than
// any job or map needs (a 4000 x 4000 maze), far less than would strain memory.
inline constexpr std::int64_t kMaxInputFileBytes = std::int64_t{16} * 1024 * 1024;

// What read_regular_file() found: the bytes, or why there are none.
struct RegularFileText {
  std::string text;     // the file's bytes when `problem` is empty
  std::string problem;  // e.g. "does not exist", "is a FIFO (named pipe), not a regular file"
};

// Reads the regular file at `path` (symlinks followed) if it holds at most
// `max_bytes` bytes. The type and size are checked with stat(2) before the file
// is opened, and again with fstat(2) on the descriptor, which is opened with
// O_NONBLOCK: a FIFO or device put in its place in between is refused, never
// waited on. `problem` reads after the file's name in a message ("'x.txt' " +
// problem). Reentrant; throws only std::bad_alloc.
RegularFileText read_regular_file(const std::filesystem::path& path,
                                  std::int64_t max_bytes = kMaxInputFileBytes);

struct JobInput {
  std::string key;   // the job file's key that names it, e.g. "maze.map_file"
  std::string path;  // as resolved against the job file's folder, lexically normal
  std::string text;  // the file's bytes
};

// The project's jobs/ folder (the source tree ggk was built from), where a
// relative input name missing beside the job is looked up next; empty when the
// build does not know it.
std::filesystem::path project_jobs_dir();

// Reads `name` (relative to job_dir; a relative name missing there is read from
// project_jobs_dir() instead), the value of `key` in `table`, with
// read_regular_file(); `what` names the kind of file in messages ("map file").
// Throws JobError at `key` when the file does not exist (in either place), is a
// directory, a FIFO, a device, a symlink loop, larger than kMaxInputFileBytes or
// cannot be read.
JobInput read_job_input(const TomlTableReader& table, std::string_view key,
                        const std::filesystem::path& job_dir, const std::string& name,
                        std::string_view what);

}  // namespace ggk::engine
