#include "support/job_text.hpp"

#include "engine/tasks/task_list.hpp"
#include "support/files.hpp"

namespace ggk::test_support {

std::string substitute(std::string text, const std::string& key, const std::string& value) {
  const std::string pattern = "%" + key + "%";
  for (std::size_t at = text.find(pattern); at != std::string::npos;
       at = text.find(pattern, at + value.size())) {
    text.replace(at, pattern.size(), value);
  }
  return text;
}

namespace {

// [begin, end) of line `line` (1-based) of `text`, without its newline.
std::pair<std::size_t, std::size_t> line_bounds(const std::string& text, int line) {
  std::size_t begin = 0;
  for (int i = 1; i < line; ++i) begin = text.find('\n', begin) + 1;
  return {begin, text.find('\n', begin)};
}

}  // namespace

std::string with_line(std::string text, int line, const std::string& replacement) {
  const auto [begin, end] = line_bounds(text, line);
  return text.replace(begin, end - begin, replacement);
}

std::string without_line(std::string text, int line) {
  const auto [begin, end] = line_bounds(text, line);
  return text.erase(begin, end + 1 - begin);
}

const char* const kBadJobHeader = R"(name = "bad"
task = "maze"
runs = 2
seed = 1
[sweep]
kernels = [4, 8]
sigma = [2.0]
[output]
file = "%DIR%/out/bad.h5"
)";

std::string header_with(int line, const std::string& text) {
  return with_line(kBadJobHeader, line, text);
}

std::string header_without(int line) {
  return without_line(kBadJobHeader, line);
}

engine::JobLoadOptions no_output_check() {
  engine::JobLoadOptions options;
  options.check_output = false;
  return options;
}

engine::JobSpec parse_unchecked(const std::string& text, const std::filesystem::path& source) {
  return engine::parse_job(text, source, engine::task_tables(), no_output_check());
}

std::filesystem::path write_job(const std::filesystem::path& dir, const std::string& name,
                                const std::string& text) {
  return write_file(dir / name, substitute(text, "DIR", dir.string()));
}

}  // namespace ggk::test_support
