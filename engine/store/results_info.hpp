#pragma once
// `ggk info FILE`: what a results file holds (job, runs complete, and the mean of
// each metric per sweep point over the complete runs), as plain text.

#include <filesystem>
#include <ostream>

namespace ggk::engine {

// Throws UsageError when the file cannot be opened or is not a ggk results file.
void print_results_info(const std::filesystem::path& file, std::ostream& out);

}  // namespace ggk::engine
