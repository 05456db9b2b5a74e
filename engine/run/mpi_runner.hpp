#pragma once
// `mpirun -np N ggk run JOB [-j T]`: one job over MPI ranks, one results file.
//
// Rank 0 owns the results file exactly as a single process does (run_job's
// create / resume / overwrite rules and input checks, the one writer thread) and
// hands out the pending runs one at a time to whichever rank asks. Every rank
// computes runs with T oneTBB threads; rank 0 computes too, on a thread of its
// own. A finished run travels to rank 0 as the bytes of an in-memory HDF5 file
// holding its group (store/run_store.hpp: run_image) and is copied into the
// results file there, so the file holds what a single process writes: the same
// datasets and attributes for any N and T (`ggk diff` says so).
//
// Every rank reads the job file itself (a cluster's shared file system); a rank
// whose job text or input files differ from rank 0's stops the job. Errors of any
// rank are printed once, by rank 0; so are progress and the final line.
//
// A stop signal (mpirun's SIGTERM to every rank on a Ctrl-C, a scheduler's):
// each worker tells rank 0 and exits once rank 0 has reported; rank 0 prints an
// interruption, the runs in flight and the resume command (stop_signals.hpp),
// exit 128 + signal. A rank that dies: under plain mpirun the launcher then
// sends the others SIGTERM, and the dead rank is the one that does not report
// it: rank 0 names it with its run (exit 1). A rank that stops answering for
// `rank_timeout` seconds while the others live on (mpirun --enable-recovery,
// srun) stops the job the same way.
// Every run already written stays complete, and `ggk run --resume` with any
// number of ranks (or none) finishes the job.
//
// Built only with GGK_WITH_MPI. MPI is initialised only when a launcher started
// the process (launched_by_mpi()), so a plain `ggk run` never touches it.

#include <filesystem>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"

namespace ggk::engine {

// True when the environment shows an MPI launcher (mpirun/mpiexec, srun, PMI/PMIx).
bool launched_by_mpi();

// MPI_Init_thread (MPI_THREAD_FUNNELED: only the main thread calls MPI) and
// MPI_Finalize. One per process.
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0;
  int size_ = 1;
};

struct MpiRunOptions {
  RunOptions run;
  JobLoadOptions load;
  double rank_timeout_seconds = 60.0;  // silence after which a rank counts as dead
};

// The whole `ggk run` on every rank of the session. Rank 0 prints every message
// and the final line; returns the exit status (0, 1 internal error, 2 user error)
// on every rank.
int run_job_over_mpi(const MpiSession& session, const std::filesystem::path& job_path,
                     const MpiRunOptions& options);

}  // namespace ggk::engine
