#pragma once
// Opening a job's results file for writing, with every rule of `ggk run` about
// it (a single process and rank 0 of an MPI job alike):
//  - the output is locked first (store/output_lock.hpp: "<output>.lock"), so a
//    second ggk on the same output is refused before anything is touched, with
//    or without HDF5's own file locking;
//  - a new file, or the replacement of an existing one (--overwrite), is written
//    under "<output>.part" (exclusive create) and takes the output's name by an
//    atomic rename when its first run is written and flushed: until then the
//    old results stay as they were, and a kill, Ctrl-C, full disk or error
//    leaves them untouched (the .part file of a dead ggk is removed by the next
//    ggk on that output). So a kill never leaves an empty results file;
//    `--resume` on an empty one (made by something else) starts it afresh;
//  - --resume continues a results file of the same job: the jobs are compared
//    as parsed TOML (a comment edit does not matter; a changed key is named),
//    the input files by content; the runs marked complete are read in full
//    (every dataset's checksum, verify_run) and a damaged one is computed
//    again; whatever a killed writer left is discarded; a file damaged beyond
//    its runs (cut short, a damaged summary or group) is not resumed in place:
//    its whole runs are copied into a new "<output>.part", which replaces it
//    with its first write, and the damaged file is kept as <stem>.damaged.h5
//    (salvage_results.hpp);
//  - from the moment the lock is held, a SIGINT, SIGTERM or SIGHUP removes the
//    lock and prints the command that goes on, as in the rest of `run` (also
//    while --resume reads its output back, which takes ~0.2 s per MB; the
//    reading child dies with its parent: isolated_reading.hpp);
//  - an output that exists without --resume or --overwrite, is not a regular
//    file, or is another job's, is a UsageError (exit status 2) and is left as
//    it was.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_spec.hpp"
#include "engine/job/study.hpp"
#include "engine/run/results_target.hpp"
#include "engine/run/stop_signals.hpp"

namespace ggk::engine {

struct RunOptions;

struct OpenedResults {
  ResultsTarget target;  // declared first: outlives the file
  // Installed once the lock is held (stop_signals.hpp); the JobWriter takes it
  // over. After the target: gone before the lock is released.
  std::unique_ptr<StopSignals> stop_signals;
  Hdf5File file;
  // Runs still to compute, configuration by configuration, each ascending.
  std::vector<WorkUnit> pending;
  std::int32_t skipped = 0;        // runs of the selection already complete
  std::vector<std::string> notes;  // what the caller must tell the user (damage, salvage)
  std::vector<std::string> info;   // what it tells unless quiet (-q): a grown file
};

// A study's file (a plain job: study_of(job)): its configurations' groups, and
// its units; --runs selects the same runs of every configuration.
// under_mpi: the resume command a stop signal prints is the MPI one (rank 0).
OpenedResults open_results(const Study& study, const RunOptions& options, bool under_mpi = false);

// The version of this ggk and the `git describe` of its source when it was
// configured: what every results file records (ggk_version, git).
std::string ggk_version_text();  // "0.1.0 (v0.1-12-gabcdef)"

}  // namespace ggk::engine
