#include "engine/job/job_input.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "engine/job/toml_table_reader.hpp"

namespace ggk::engine {

JobInput read_job_input(const TomlTableReader& table, std::string_view key,
                        const std::filesystem::path& job_dir, const std::string& name,
                        std::string_view what) {
  const std::filesystem::path path = job_dir / name;
  JobInput input{table.key_path(key), path.lexically_normal().string(), {}};
  const std::string shown = std::string(what) + " '" + name + "' (" + input.path + ")";
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) table.fail(key, shown + " does not exist");
  if (std::filesystem::is_directory(status)) table.fail(key, shown + " is a directory");
  std::ifstream file(path, std::ios::binary);
  if (!file) table.fail(key, "cannot read " + shown + ": " + std::strerror(errno));
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) table.fail(key, "cannot read " + shown + ": " + std::strerror(errno));
  input.text = text.str();
  return input;
}

std::string input_attribute_name(const JobInput& input) {
  return "input:" + input.key;
}

}  // namespace ggk::engine
