// ggk: the command line. Parses (engine/cli/command_line.hpp) and dispatches to
// one function per command (engine/cli/*_command.hpp); user errors become one
// clear message on stderr and exit status 2 (engine/cli/exit_status.hpp); results
// go only to HDF5 files. Under an MPI launcher (mpirun, srun) `ggk run` spreads
// the runs over the ranks (engine/run/mpi_runner.hpp); everything else runs on
// rank 0 alone.

#include <omp.h>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "engine/cli/command_line.hpp"
#include "engine/cli/diff_command.hpp"
#include "engine/cli/exit_status.hpp"
#include "engine/cli/info_command.hpp"
#include "engine/cli/merge_command.hpp"
#include "engine/cli/run_command.hpp"
#include "engine/cli/validate_command.hpp"
#include "engine/cli/verify_command.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/address_space.hpp"
#if GGK_WITH_MPI
#include "engine/run/mpi_runner.hpp"
#endif

int main(int argc, char** argv) {
  namespace engine = ggk::engine;
  // Under ulimit -v, OpenBLAS's thread pool can spin forever: restart without it.
  engine::restart_without_blas_pool(argv);
  // Parallelism belongs to oneTBB: no OpenMP teams inside SuiteSparse calls.
  omp_set_num_threads(1);
  // As typed (before an MPI launcher's library may edit argv): the commands
  // ggk prints to resume repeat it.
  const std::vector<std::string> invocation(argv, argv + argc);
#if GGK_WITH_MPI
  std::optional<engine::MpiSession> mpi;
  if (engine::launched_by_mpi()) mpi.emplace(argc, argv);
  engine::MpiSession* const session = mpi ? &*mpi : nullptr;
  const bool quiet_rank = mpi && mpi->rank() != 0;
#else
  engine::MpiSession* const session = nullptr;
  const bool quiet_rank = false;
#endif

  engine::CommandLine line;
  try {
    engine::check_spelling(line.app, argc, argv);
  } catch (const engine::UsageError& e) {
    if (!quiet_rank) std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return engine::kUserErrorStatus;
  }
  try {
    line.app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status =
        quiet_rank ? (e.get_exit_code() == 0 ? 0 : engine::kUserErrorStatus) : line.app.exit(e);
    return status == 0 ? 0 : engine::kUserErrorStatus;
  }
  return engine::exit_status_of(
      [&] {
        if (*line.run) return engine::run_command(line, invocation, quiet_rank, session);
        if (quiet_rank) return 0;  // the other commands run on rank 0 alone
        if (*line.validate) return engine::validate_command(line);
        if (*line.info) return engine::info_command(line);
        if (*line.verify) return engine::verify_command(line);
        if (*line.diff) return engine::diff_command(line);
        if (*line.merge) return engine::merge_command(line, invocation);
        return 0;
      },
      quiet_rank);
}
