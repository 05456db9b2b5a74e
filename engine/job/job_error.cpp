#include "engine/job/job_error.hpp"

#include <utility>

namespace ggk::engine {
namespace {

// A message's detail is built from shortened values; this bounds what a caller
// forgot to shorten.
constexpr std::size_t kMaxDetailCharacters = 2000;

bool is_continuation_byte(char c) {
  return (static_cast<unsigned char>(c) & 0xC0) == 0x80;
}

std::string format_message(const std::string& file, JobFileLocation location,
                           const std::string& key_path, const std::string& detail) {
  std::string message = file;
  if (location.line > 0) {
    message += ':' + std::to_string(location.line) + ':' + std::to_string(location.column);
  }
  message += ": ";
  if (!key_path.empty()) message += display_key(key_path) + ": ";
  return message + shortened(detail, kMaxDetailCharacters);
}

}  // namespace

std::string display_key(const std::string& key_path) {
  // The last dot outside double quotes: a quoted key ("arm.links", a study
  // axis) is one key, printed as written ([sweep] "arm.links", not
  // [sweep."arm] links").
  std::size_t dot = std::string::npos;
  bool quoted = false;
  for (std::size_t i = 0; i < key_path.size(); ++i) {
    if (key_path[i] == '"') quoted = !quoted;
    if (key_path[i] == '.' && !quoted) dot = i;
  }
  if (dot == std::string::npos) return shortened(key_path);
  return '[' + shortened(std::string_view(key_path).substr(0, dot)) + "] " +
         shortened(std::string_view(key_path).substr(dot + 1));
}

std::string shortened(std::string_view text, std::size_t max_characters) {
  std::size_t characters = 0;
  std::size_t cut = text.size();  // byte offset after max_characters characters
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (is_continuation_byte(text[i])) continue;
    if (characters == max_characters) cut = i;
    ++characters;
  }
  if (characters <= max_characters) return std::string(text);
  return std::string(text.substr(0, cut)) + "\u2026(" + std::to_string(characters) + " characters)";
}

JobError::JobError(std::string file, JobFileLocation location, std::string key_path,
                   std::string detail)
    : std::runtime_error(format_message(file, location, key_path, detail)),
      file_(std::move(file)),
      location_(location),
      key_path_(std::move(key_path)),
      detail_(std::move(detail)) {}

}  // namespace ggk::engine
