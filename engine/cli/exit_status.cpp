#include "engine/cli/exit_status.hpp"

#include <cstdio>
#include <exception>
#include <new>

#include "engine/job/job_error.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/address_space.hpp"
#include "engine/run/job_runner.hpp"

namespace ggk::engine {

int exit_status_of(const std::function<int()>& command, bool quiet_rank) {
  try {
    return command();
  } catch (const JobError& e) {
    if (!quiet_rank) std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return kUserErrorStatus;
  } catch (const UsageError& e) {
    if (!quiet_rank) std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return kUserErrorStatus;
  } catch (const RunFailure& e) {
    std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {  // the machine's memory or the user's limit, not a bug
    std::fprintf(stderr, "ggk: error: not enough memory: an allocation failed%s\n",
                 address_space_limit_words().c_str());
    return kUserErrorStatus;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggk: internal error: %s\n", e.what());
    return 1;
  }
}

}  // namespace ggk::engine
