// libFuzzer target for the job-file reader: parse_job() on arbitrary bytes with
// every registered task's table. Any input must parse or throw JobError (or
// UsageError); any other exception, a crash, a sanitizer report or a hang is a
// finding. See fuzz/README.md.
//
// The job is named <scratch>/fuzz.toml, where <scratch> is a fresh temporary
// folder holding only copies of the shipped inputs (maps/four-rooms.txt,
// arenas/default.toml), so that the seed jobs read their files and relative file
// names in fuzzed jobs find nothing else.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/tasks/task_list.hpp"

namespace {

namespace fs = std::filesystem;

fs::path scratch_folder;

void remove_scratch_folder() {
  std::error_code ignored;
  fs::remove_all(scratch_folder, ignored);
}

// <scratch>/fuzz.toml, made on the first call.
const fs::path& job_path() {
  static const fs::path path = [] {
    std::string pattern = (fs::temp_directory_path() / "ggk-fuzz-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) std::abort();
    scratch_folder = pattern;
    std::atexit(remove_scratch_folder);
    const fs::path jobs = fs::path(GGK_SOURCE_DIR) / "jobs";
    for (const char* input : {"maps/four-rooms.txt", "arenas/default.toml"}) {
      fs::create_directories((scratch_folder / input).parent_path());
      fs::copy_file(jobs / input, scratch_folder / input);
    }
    return scratch_folder / "fuzz.toml";
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path& path = job_path();
  std::string text(reinterpret_cast<const char*>(data), size);
  ggk::engine::JobLoadOptions options;
  options.check_output = false;  // the output file's folder is the CLI's concern
  try {
    ggk::engine::parse_job(std::move(text), path, ggk::engine::task_tables(), options);
  } catch (const ggk::engine::JobError&) {
  } catch (const ggk::engine::UsageError&) {
  }
  return 0;
}
