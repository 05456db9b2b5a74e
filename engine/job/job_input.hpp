#pragma once
// A file a job file names (the maze's map_file, the Khepera's arena_file), read
// whole when the job is loaded. Its text is stored with the results (root
// attribute "input:<key>") and `ggk run --resume` refuses a results file whose
// inputs differ from the files now on disk, as it refuses another job file.

#include <filesystem>
#include <string>
#include <string_view>

namespace ggk::engine {

class TomlTableReader;

struct JobInput {
  std::string key;   // the job file's key that names it, e.g. "maze.map_file"
  std::string path;  // as resolved against the job file's folder, lexically normal
  std::string text;  // the file's bytes
};

// Reads `name` (relative to job_dir), the value of `key` in `table`; `what` names
// the kind of file in messages ("map file"). Throws JobError at `key` when the
// file does not exist, is a directory or cannot be read.
JobInput read_job_input(const TomlTableReader& table, std::string_view key,
                        const std::filesystem::path& job_dir, const std::string& name,
                        std::string_view what);

// The name of the results file's root attribute that holds `input`'s text.
std::string input_attribute_name(const JobInput& input);

}  // namespace ggk::engine
