#include "engine/job/job_error.hpp"

#include <utility>

namespace ggk::engine {
namespace {

std::string format_message(const std::string& file, JobFileLocation location,
                           const std::string& key_path, const std::string& detail) {
  std::string message = file;
  if (location.line > 0) {
    message += ':' + std::to_string(location.line) + ':' + std::to_string(location.column);
  }
  message += ": ";
  if (!key_path.empty()) message += display_key(key_path) + ": ";
  return message + detail;
}

}  // namespace

std::string display_key(const std::string& key_path) {
  const std::size_t dot = key_path.rfind('.');
  if (dot == std::string::npos) return key_path;
  return '[' + key_path.substr(0, dot) + "] " + key_path.substr(dot + 1);
}

std::string single_quoted(std::string_view text) {
  // Built by appending: GCC 12 at -O3 warns (-Wrestrict, a false positive) on
  // "'" + std::string.
  std::string result;
  result.reserve(text.size() + 2);
  result += '\'';
  result += text;
  result += '\'';
  return result;
}

JobError::JobError(std::string file, JobFileLocation location, std::string key_path,
                   std::string detail)
    : std::runtime_error(format_message(file, location, key_path, detail)),
      file_(std::move(file)),
      location_(location),
      key_path_(std::move(key_path)),
      detail_(std::move(detail)) {}

}  // namespace ggk::engine
