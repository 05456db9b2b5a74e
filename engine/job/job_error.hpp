#pragma once
// The one exception a job file raises when it cannot be run: TOML syntax, unknown
// keys, wrong types, out-of-range values, missing files. what() reads
//
//   FILE:LINE:COLUMN: [TABLE] KEY: DETAIL
//
// e.g. "jobs/bad.toml:12:1: [sweep] kernels: expected ... got -3". LINE:COLUMN is
// left out when the error has no place in the file (a missing table, an unreadable
// file); "[TABLE] " is left out for top-level keys, and "KEY: " for TOML syntax
// errors. The CLI prints what() and exits with status 2. Values a message echoes
// are shortened (shortened() below); so are the key and, as a last guard, DETAIL.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ggk::engine {

// 1-based; line 0 means "no place in the file".
struct JobFileLocation {
  std::int32_t line = 0;
  std::int32_t column = 0;
};

class JobError : public std::runtime_error {
 public:
  // key_path: dotted path of the key ("sweep.kernels", "runs"); empty for errors
  // that belong to no key (syntax errors).
  JobError(std::string file, JobFileLocation location, std::string key_path, std::string detail);

  const std::string& file() const { return file_; }
  std::int32_t line() const { return location_.line; }
  std::int32_t column() const { return location_.column; }
  const std::string& key_path() const { return key_path_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  JobFileLocation location_;
  std::string key_path_;
  std::string detail_;
};

// "[sweep] kernels" for "sweep.kernels", "runs" for "runs".
std::string display_key(const std::string& key_path);

// The longest value a message echoes, in characters (UTF-8 code points).
inline constexpr std::size_t kMaxEchoedCharacters = 80;

// `text` when it has at most max_characters characters, else its first
// max_characters characters and "…(N characters)": messages echo values from the
// job file (names, keys, file names) through it, so that a 1 MB value gives a
// short message. Never splits a UTF-8 sequence.
std::string shortened(std::string_view text, std::size_t max_characters = kMaxEchoedCharacters);

}  // namespace ggk::engine
