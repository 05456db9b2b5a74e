#include "engine/run/job_writer.hpp"

#include <utility>

#include "engine/job/sweep.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/run_extension.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

StopSignals::Report stop_report(const ResultsTarget& target, const GoOnText& go_on) {
  return {target.output(), target.temporary(), target.lock_file(), go_on.published,
          go_on.unpublished};
}

}  // namespace

JobWriter::JobWriter(const Study& study, const RunOptions& options, OpenedResults opened,
                     std::int32_t runs_to_write, StopSignals::Mode mode)
    : study_(study),
      target_(std::move(opened.target)),
      go_on_(
          go_on_text(study.job(), options, target_.output(), mode == StopSignals::Mode::kRecord)),
      stop_signals_(std::move(opened.stop_signals)),
      progress_(std::in_place, runs_to_write,
                static_cast<std::int32_t>(expand_points(study.configurations.front()).size()),
                options.quiet),
      writer_(std::move(opened.file), StoreWriter::kDefaultQueueCapacity,
              StoreWriter::WhenIdle::kCloseForReaders) {
  stop_signals_->set_mode(mode);
  stop_signals_->set_report(stop_report(target_, go_on_));
}

void JobWriter::committed() {
  stop_signals_->results_published();
  written_.fetch_add(1);
  progress_->run_done();
}

void JobWriter::commit(std::shared_ptr<const RunRecord> record) {
  writer_.submit([this, record = std::move(record)](Hdf5File& file) {
    const RunConfiguration& configuration = study_.configurations.at(record->configuration);
    if (record->extension) {
      extend_run(file, configuration.job, *record, expand_points(configuration));
    } else {
      write_run(file, configuration.job, *record);
    }
    target_.publish(file);  // a new file takes its name with its first run
    progress_->unit_cost(record->configuration, record->compute_seconds);
    committed();
  });
}

void JobWriter::commit_image(std::int32_t configuration, std::int32_t run,
                             std::shared_ptr<const std::vector<unsigned char>> bytes,
                             std::size_t offset, bool extension) {
  writer_.submit(
      [this, configuration, run, bytes = std::move(bytes), offset, extension](Hdf5File& file) {
        const RunConfiguration& of = study_.configurations.at(configuration);
        const std::span<const unsigned char> image(bytes->data() + offset, bytes->size() - offset);
        if (extension) {
          extend_run_from_image(file, of.job, run, image, expand_points(of));
        } else {
          write_run_image(file, of.job, run, image);
        }
        target_.publish(file);
        committed();
      });
}

void JobWriter::commit_pieces(std::int32_t configuration, std::int32_t run,
                              std::vector<RunPiece> pieces) {
  writer_.submit([this, configuration, run, pieces = std::move(pieces)](Hdf5File& file) {
    const RunConfiguration& of = study_.configurations.at(configuration);
    write_run_pieces(file, of.job, run, pieces, expand_points(of));
    target_.publish(file);
    committed();
  });
}

void JobWriter::finish() {
  writer_.wait();
  progress_.reset();  // its final line before the summary's
  writer_.submit([this](Hdf5File& file) {
    write_summary(file, study_.job());
    target_.publish(file);
  });
  writer_.close();
  stop_signals_->job_complete();
}

}  // namespace ggk::engine
