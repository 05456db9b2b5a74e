#pragma once
// The one commit path of both runners (job_runner.hpp, mpi_runner.hpp): how a
// finished run reaches a job's results file, and how the job ends there.
//
// A JobWriter takes over what open_results opened (the lock, the file, its
// .part name, the stop signals' handler) and owns the store's writer thread, the progress display
// and the stop signals (stop_signals.hpp). commit() queues a run computed here, commit_image() one
// computed by another MPI rank (an in-memory HDF5 image, store/run_store.hpp); the writer thread
// writes it whole and marks it complete, gives a new file the output's name with its first run,
// tells the stop signals so, and advances the progress. finish() waits for every queued run, closes
// the progress display, rewrites the summary in run order and closes the file. A failed write makes
// the writer fail (store_writer.hpp): commit(), wait() and finish() rethrow it.
//
// Thread-safety: commit(), commit_image(), written() and failed() may be called
// from any threads but the writer's; finish() and the destructor from one.

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/job/study.hpp"
#include "engine/run/open_results.hpp"
#include "engine/run/progress.hpp"
#include "engine/run/resume_command.hpp"
#include "engine/run/stop_signals.hpp"
#include "engine/store/run_extension.hpp"
#include "engine/store/store_writer.hpp"
#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

struct RunOptions;

class JobWriter {
 public:
  // runs_to_write: the progress display's total. mode: kStopInHandler for a
  // single process, kRecord for rank 0 of an MPI job (which then calls stop()).
  // `study` (a plain job: study_of(job)) must outlive the writer.
  JobWriter(const Study& study, const RunOptions& options, OpenedResults opened,
            std::int32_t runs_to_write, StopSignals::Mode mode);
  JobWriter(const JobWriter&) = delete;
  JobWriter& operator=(const JobWriter&) = delete;

  void commit(std::shared_ptr<const RunRecord> record);
  // The image of the run of configuration `configuration` is bytes[offset..];
  // `extension`: it holds the fits the stored run lacks (RunRecord::extension).
  void commit_image(std::int32_t configuration, std::int32_t run,
                    std::shared_ptr<const std::vector<unsigned char>> bytes, std::size_t offset,
                    bool extension);

  // A run computed in pieces on several ranks (run_pieces.hpp), every piece come:
  // written whole, as one commit (store/run_extension.hpp: write_run_pieces).
  void commit_pieces(std::int32_t configuration, std::int32_t run, std::vector<RunPiece> pieces);

  void wait() { writer_.wait(); }
  // Runs `read` (taking the Hdf5File) on the writer thread after every queued
  // write, and returns its result or rethrows what it threw (an adaptive study's
  // look reads the runs written so far).
  template <class Read>
  auto read(Read read_file) {
    return writer_.submit_and_wait(std::move(read_file)).get();
  }
  // An adaptive study's next look (progress.hpp).
  void add_runs_to_write(std::int32_t runs) { progress_->add_runs(runs); }
  // The units this process computes: their configurations' costs weigh the ETA.
  void expect_units(std::span<const WorkUnit> units) {
    for (const WorkUnit& unit : units) progress_->expect_unit(unit.configuration);
  }
  void set_stage(std::string text) { progress_->set_stage(std::move(text)); }
  // Fits another MPI rank ended (its heartbeats say how many).
  void add_remote_fits(std::int64_t fits) { progress_->add_remote_fits(fits); }
  bool failed() const { return writer_.failed(); }
  std::int32_t written() const { return written_.load(); }
  const ResultsTarget& target() const { return target_; }
  const GoOnText& go_on() const { return go_on_; }
  const StopSignals& stop_signals() const { return *stop_signals_; }

  // Waits for the queued runs, writes the summary, closes the file.
  void finish();

 private:
  void committed();  // on the writer thread, after a run is written

  const Study& study_;
  ResultsTarget target_;  // before writer_: the lock outlives the file
  const GoOnText go_on_;
  std::unique_ptr<StopSignals> stop_signals_;  // open_results's, aimed at this job's texts
  std::atomic<std::int32_t> written_{0};
  std::optional<Progress> progress_;
  StoreWriter writer_;  // last: its thread stops before the rest goes
};

}  // namespace ggk::engine
