#include "engine/cli/diff_command.hpp"

#include <iostream>
#include <ostream>

#include "engine/run/isolated_reading.hpp"
#include "engine/store/results_diff.hpp"

namespace ggk::engine {

int diff_command(const CommandLine& line) {
  std::ostream discard(nullptr);  // -q: what would be printed, dropped
  std::ostream& out = line.quiet ? discard : std::cout;
  const std::string& a = line.diff_files[0];
  const std::string& b = line.diff_files[1];
  return read_isolated({a, b}, [&] { return diff_results(a, b, out, line.diff_options) ? 0 : 1; });
}

}  // namespace ggk::engine
