#include "engine/cli/info_command.hpp"

#include <iostream>
#include <ostream>

#include "engine/run/isolated_reading.hpp"
#include "engine/store/results_info.hpp"

namespace ggk::engine {

int info_command(const CommandLine& line) {
  std::ostream discard(nullptr);  // -q: what would be printed, dropped
  std::ostream& out = line.quiet ? discard : std::cout;
  InfoOptions options = line.info_options;
  options.format = line.info_csv ? InfoFormat::kCsv : InfoFormat::kText;
  options.columns = info_column_list(line.info_columns);
  if (!line.info_paired.empty()) options.paired = parse_paired_option(line.info_paired);
  return read_isolated({line.info_path}, [&] {
    print_results_info(line.info_path, out, options);
    return 0;
  });
}

}  // namespace ggk::engine
