#pragma once
// The warnings of a job's fits (FitRecord::warning) for the closing lines of
// `ggk run`: one line per fit kind (basis and kernel count: the fits of a kind
// share their basis functions within a run), with how many of its fits carry a
// warning and the text of the first (lowest configuration, then run, then sweep
// point: the same line for any -j). Every such fit also holds its text as the
// attribute `warning` (results/README.md).
//
// Thread-safety: add() may be called from several threads at once.

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

class FitWarnings {
 public:
  void add(const RunRecord& record);
  // "pvf, 4 kernels: 3 of 12 fits, e.g. run 0: <text>" per kind with a warning.
  std::vector<std::string> lines() const;

 private:
  struct Kind {
    std::int64_t fits = 0;
    std::int64_t warned = 0;
    std::tuple<std::int32_t, std::int32_t, std::int32_t> first{INT32_MAX, INT32_MAX, INT32_MAX};
    std::string text;
  };
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, std::int32_t>, Kind> kinds_;
};

}  // namespace ggk::engine
