#pragma once
// A user error found after the job file was read (the output exists, a results
// file from another job, a file that is not a ggk results file): the CLI prints
// it and exits with status 2. Errors in the job file itself are JobErrors.

#include <stdexcept>

namespace ggk::engine {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ggk::engine
