#pragma once
// Job files for tests: placeholders filled in, lines replaced by number, jobs
// written to a scratch folder or parsed without touching the file system.

#include <filesystem>
#include <string>
#include <string_view>

#include "engine/job/job_file.hpp"
#include "engine/job/job_spec.hpp"

namespace ggk::test_support {

// `text` with every "%KEY%" replaced by `value`.
std::string substitute(std::string text, const std::string& key, const std::string& value);

// `text` with its line `line` (1-based, without its newline) replaced by
// `replacement`, which may hold several lines.
std::string with_line(std::string text, int line, const std::string& replacement);
// `text` without its line `line` (1-based).
std::string without_line(std::string text, int line);

// A valid maze job of 2 tiny runs (the map is the task's default), lines 1-9:
// name "bad", runs = 2 on line 3, seed on 4, [sweep] kernels on 6 and sigma on
// 7, [output] file = "%DIR%/out/bad.h5" on line 9. The job files' and the CLI's
// malformed-job tables start from it.
extern const char* const kBadJobHeader;
// kBadJobHeader with line `line` replaced, or without it.
std::string header_with(int line, const std::string& text);
std::string header_without(int line);

// Load options that leave the [output] file unchecked: for jobs parsed, not run.
engine::JobLoadOptions no_output_check();

// `text` parsed as the job file `source` with every registered task, output unchecked.
engine::JobSpec parse_unchecked(const std::string& text,
                                const std::filesystem::path& source = "job.toml");

// Writes `text` to `dir/name` with "%DIR%" replaced by `dir`; returns the path.
std::filesystem::path write_job(const std::filesystem::path& dir, const std::string& name,
                                const std::string& text);

}  // namespace ggk::test_support
