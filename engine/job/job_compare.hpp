#pragma once
// Do two job-file texts describe the same job? Compared as parsed TOML (keys,
// types and values), so comments, blank lines, key order and quoting style do
// not count; used where a results file's recorded job meets the job file again
// (`ggk run --resume`, `ggk merge`).

#include <optional>
#include <string>
#include <string_view>

namespace ggk::engine {

// Empty when `recorded` and `current` are the same job; otherwise the first
// difference in words, e.g. "[sweep] kernels: [10, 20] in the results file, [10, 30] in
// the job file" or "runs: only in the job file" (the labels name the two). Texts
// that do not parse as TOML are compared as text.
std::optional<std::string> job_difference(std::string_view recorded, std::string_view current,
                                          std::string_view recorded_label = "the results file",
                                          std::string_view current_label = "the job file");

}  // namespace ggk::engine
