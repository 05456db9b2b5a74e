#include "engine/run/open_results.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "engine/job/job_compare.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/job_input.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/existing_output.hpp"
#include "engine/run/isolated_reading.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/run/reading_memory_cap.hpp"
#include "engine/run/resume_command.hpp"
#include "engine/run/resume_compatibility.hpp"
#include "engine/run/salvage_results.hpp"
#include "engine/store/configuration_groups.hpp"
#include "engine/store/one_line.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/results_verify.hpp"
#include "engine/store/run_extension.hpp"
#include "engine/store/run_store.hpp"
#include "engine/store/utc_time.hpp"
#include "kernels/blas_runtime.hpp"
// GGK_GIT_DESCRIBE, written at build time (engine/CMakeLists.txt).
#include "ggk_git_describe.hpp"

#ifndef GGK_VERSION
#define GGK_VERSION "unknown"
#endif

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

// The results file cannot be opened or created for reasons of the user's making
// (not an HDF5 file, no permission): a UsageError, reported like a bad -o.
template <class Open>
Hdf5File open_as_user(Open&& open) {
  try {
    return open();
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw UsageError(e.what());
  }
}

// Which runs a shard file is for (root attribute runs_selected = [A, B]); none
// for a whole job's file.
std::optional<RunsSelected> selection(const JobSpec& job, const std::optional<RunRange>& runs) {
  if (!runs || (runs->first == 0 && runs->last == job.runs)) return std::nullopt;
  return RunsSelected{runs->first, runs->last};
}

// Which run configurations an adaptive study's shard file is for, and the
// study's cells; none for a whole study's file.
std::optional<ConfigurationsSelected> configurations_selected(const RunOptions& options) {
  if (!options.configuration_shard) return std::nullopt;
  const AdaptiveScope& scope = options.configuration_shard->scope;
  return ConfigurationsSelected{
      std::vector<std::int64_t>(scope.configurations.begin(), scope.configurations.end()),
      scope.cells.value_or(0)};
}

// HDF5's flush writes the superblock, with the file's new end, before it
// extends the file; when the extension fails (a full disk) the file is left
// shorter than its superblock says and no longer opens ("truncated file: ...
// stored_eof = N"). Everything a successful flush wrote is still there: the
// missing tail is space of the write that failed. Extending the file to N
// (zeros) lets it open; the failed write's leftovers are in the staging group,
// which resume discards, and every kept run is read back (verify_run).
bool extend_truncated(const fs::path& output, const std::string& error,
                      std::vector<std::string>& notes) {
  const std::string marker = "stored_eof = ";
  const std::size_t at = error.find(marker);
  if (error.find("truncated file") == std::string::npos || at == std::string::npos) return false;
  const unsigned long long stored_end =
      std::strtoull(error.c_str() + at + marker.size(), nullptr, 10);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(output, ec);
  if (ec || stored_end <= size) return false;
  if (::truncate(output.c_str(), static_cast<off_t>(stored_end)) != 0) return false;
  notes.push_back(output.string() + " was cut short by a write that failed (a full disk?): " +
                  "extended from " + std::to_string(size) + " to " + std::to_string(stored_end) +
                  " bytes to open it; its complete runs are checked");
  return true;
}

// Opened as the writer opens it between runs (Hdf5File::reopen_for_writer): a
// reader holding the file (a notebook's h5py handle, a `ggk info` loop) keeps
// HDF5's lock, so after a bounded wait the file is written without HDF5's lock;
// ggk's own output lock, held here, keeps out a second writer.
Hdf5File open_for_resume(const fs::path& output, std::vector<std::string>& notes) {
  try {
    return Hdf5File::reopen_for_writer(output);
  } catch (const std::runtime_error& e) {
    if (!extend_truncated(output, e.what(), notes)) throw UsageError(e.what());
  }
  return open_as_user([&] { return Hdf5File::reopen_for_writer(output); });
}

ResultsHeader new_header(const Study& study, const RunOptions& options);

Hdf5File resume(const Study& study, const RunOptions& options, const fs::path& output,
                std::vector<std::vector<std::int32_t>>& complete, std::vector<std::string>& notes,
                std::vector<std::string>& info) {
  // The job is compared on a read-only handle first: HDF5 cuts a file opened for
  // writing to its allocated end when it closes it, which would drop a killed
  // writer's staging on a resume that is then refused (a refusal touches
  // nothing). A file that does not open read-only goes on as before (a
  // truncated one is extended by open_for_resume, a damaged one salvaged).
  std::optional<Hdf5File> reading;
  try {
    reading.emplace(Hdf5File::open_read_only(output));
  } catch (const std::runtime_error&) {
  }
  std::optional<bool> grows_into;  // the comparison's answer, when it read the file
  if (reading) {
    grows_into = check_same_job(*reading, study, output);
    reading->close();
  }
  Hdf5File file = open_for_resume(output, notes);
  const bool grown = grows_into ? *grows_into : check_same_job(file, study, output);
  align_configurations(file, study, output);
  if (grown) {
    // The file now holds the larger job's runs (some not computed yet).
    rewrite_job_attributes(file, new_header(study, options));
    file.flush();
    const std::size_t configurations = study.configurations.size();
    info.push_back("growing " + output.string() + " to the job's " +
                   std::to_string(study.job().runs) + " runs" +
                   (configurations > 1
                        ? " x " + std::to_string(configurations) + " run configurations"
                        : std::string()) +
                   " x " + std::to_string(expand_points(study.configurations.front()).size()) +
                   " sweep points: its complete runs are kept");
  }
  for (const RunConfiguration& configuration : study.configurations) {
    const JobSpec& job = configuration.job;
    const std::string location = runs_location(job);
    std::vector<std::int32_t> kept = prepare_for_resume(file, job);
    // A run marked complete is kept only if every dataset in it reads back with a
    // good checksum; a damaged one is dropped and computed again.
    std::erase_if(kept, [&](std::int32_t run) {
      const std::optional<std::string> damage = verify_run(file, location, run);
      if (!damage) return false;
      notes.push_back(unit_words(study, {configuration.index, run}) + " of " + output.string() +
                      " is damaged (" + *damage + "): computing it again");
      discard_run(file, location, run);
      return true;
    });
    complete.push_back(std::move(kept));
  }
  // Damage outside the runs (the summary, a group's attributes) is not computed
  // again: the caller salvages the file instead (salvage_results.hpp).
  if (const std::optional<std::string> damage = verify_beyond_runs(file)) {
    throw std::runtime_error(*damage);
  }
  // A resumed file is for the selection it was last run with.
  write_runs_selected(file, selection(study.job(), options.runs));
  write_configurations_selected(file, configurations_selected(options));
  file.flush();
  return file;
}

// The root attributes of a new results file of `study`.
ResultsHeader new_header(const Study& study, const RunOptions& options) {
  const JobSpec& job = study.job();
  ResultsHeader header;
  header.job = job.source_text;
  header.job_file = job.source_file.string();
  for (const JobInput& input : job.inputs) header.inputs.push_back({input.key, input.text});
  header.ggk_version = GGK_VERSION;
  header.git = GGK_GIT_DESCRIBE;
  header.blas = kernels::blas_info().name;
  header.created = utc_now();
  header.task = job.task;
  header.runs = job.runs;
  for (const std::string& text : job.overrides) {
    header.job_overrides += (header.job_overrides.empty() ? "" : "\n") + text;
  }
  for (const std::string& text : job.sweeps) {
    header.job_sweeps += (header.job_sweeps.empty() ? "" : "\n") + text;
  }
  header.job_resolved = resolved_of(study).text();
  header.runs_selected = selection(job, options.runs);
  header.configurations_selected = configurations_selected(options);
  return header;
}

Hdf5File create_new(const Study& study, const RunOptions& options, const fs::path& path) {
  Hdf5File file =
      open_as_user([&] { return Hdf5File::create(path, Hdf5File::CreateMode::kFailIfExists); });
  write_results_header(file, new_header(study, options));
  file.create_group("/" + study.job().task);
  for (const RunConfiguration& configuration : study.configurations) {
    if (!configuration.job.configuration_group.empty()) {
      write_configuration_group(file, configuration);
    }
  }
  file.flush();
  return file;
}

// A new file of `study` under `temporary` holding every run of the damaged
// `output` that reads back whole (salvage_results.hpp).
Hdf5File salvage(const Study& study, const RunOptions& options, const fs::path& output,
                 const fs::path& temporary, const std::string& damage, bool crashes,
                 std::vector<std::vector<std::int32_t>>& complete,
                 std::vector<std::string>& notes) {
  const fs::path kept = keep_damaged_aside(output);
  std::optional<Hdf5File> fresh;
  SalvageCount count;
  try {
    fresh.emplace(create_new(study, options, temporary));
    try {
      if (crashes) throw std::runtime_error("reading it crashes HDF5");
      const Hdf5File damaged = Hdf5File::open_read_only(output);
      complete = copy_readable_runs(damaged, *fresh, study, count);
    } catch (const std::runtime_error&) {  // not even its root reads: nothing to copy
      complete.assign(study.configurations.size(), {});
      count.lost_lists = static_cast<std::int64_t>(study.configurations.size());
    }
    fresh->flush();
  } catch (...) {
    ::unlink(kept.c_str());  // the output still holds it
    throw;
  }
  std::string lost;
  if (count.unreadable > 0) lost += "; " + std::to_string(count.unreadable) + " damaged runs";
  if (count.lost_lists > 0 && study.configurations.size() == 1) {
    lost += "; every run, as its list of runs is damaged";
  } else if (count.lost_lists > 0) {
    lost += "; every run of " + std::to_string(count.lost_lists) + " of the " +
            std::to_string(study.configurations.size()) +
            " run configurations, as their lists of runs are damaged";
  }
  if (crashes) {
    notes.push_back(output.string() + " cannot be read (" + damage +
                    "): nothing of it is copied, every run is computed again into a new file, "
                    "which replaces it with its first write. The damaged file stays as " +
                    kept.string() + " (delete it when you no longer need it)");
    return std::move(*fresh);
  }
  if (count.lost_lists == 0 && count.copied == count.listed) {
    // Every run group it lists was complete, read back whole and is in the new
    // file: what else it held (a killed writer's staging, its summary) is
    // computed again, so a copy of it would keep nothing (stop 41's campaign, F6).
    ::unlink(kept.c_str());
    notes.push_back(output.string() + " cannot be resumed in place (" + damage + "): its " +
                    std::to_string(count.copied) +
                    " complete runs all read back whole and were copied into a new file, which "
                    "replaces it with its first write; nothing of it is lost, so no copy of it "
                    "is kept");
    return std::move(*fresh);
  }
  notes.push_back(output.string() + " cannot be resumed in place (" + damage + "): its " +
                  std::to_string(count.copied) +
                  " complete runs that read back whole were copied into a new file, which "
                  "replaces it with its first write, and the rest is computed again" +
                  (lost.empty() ? std::string() : " (" + lost.substr(2) + ")") +
                  ". The damaged file stays as " + kept.string() +
                  " (delete it when you no longer need it)");
  return std::move(*fresh);
}

// The units of the selected runs still to compute, configuration by
// configuration (`complete`: each one's complete runs, ascending): a run not
// complete whole; a complete run of a study grown by fit-level values with the
// fits it lacks (store/run_extension.hpp), said in opened.info; the others skipped.
void add_pending_units(const Study& study, const RunOptions& options,
                       const std::vector<std::vector<std::int32_t>>& complete,
                       const fs::path& output, OpenedResults& opened) {
  const std::int32_t first = options.runs ? options.runs->first : 0;
  const std::int32_t last = options.runs ? options.runs->last : study.job().runs;
  std::int64_t extended = 0, new_fits = 0;
  std::vector<bool> selected(study.configurations.size(), !options.configuration_shard);
  if (options.configuration_shard) {
    for (const std::int32_t c : options.configuration_shard->scope.configurations) {
      selected.at(static_cast<std::size_t>(c)) = true;
    }
  }
  for (std::size_t c = 0; c < study.configurations.size(); ++c) {
    if (!selected[c]) continue;  // another shard's
    const RunConfiguration& configuration = study.configurations[c];
    const std::vector<SweepPoint> points = expand_points(configuration);
    for (std::int32_t run = first; run < last; ++run) {
      if (!std::binary_search(complete[c].begin(), complete[c].end(), run)) {
        opened.pending.push_back({static_cast<std::int32_t>(c), run});
        continue;
      }
      // A complete run of a study grown by fit-level values lacks their fits:
      // only they are computed (store/run_extension.hpp). An adaptive study's
      // runs hold the points their looks needed: its looks extend them
      // (run/adaptive_runner.hpp).
      if (study.job().adaptive) {
        ++opened.skipped;
        continue;
      }
      std::vector<std::int32_t> lacking;
      try {
        lacking = lacking_points(opened.file, runs_location(configuration.job), run, points);
      } catch (const std::runtime_error& e) {
        throw UsageError("cannot resume " + output.string() + ": " + e.what());
      }
      if (lacking.empty()) {
        ++opened.skipped;
      } else {
        ++extended;
        new_fits += static_cast<std::int64_t>(lacking.size());
        opened.pending.push_back({static_cast<std::int32_t>(c), run, std::move(lacking), true});
      }
    }
  }
  if (extended > 0) {
    opened.info.push_back(
        "growing " + std::to_string(extended) + " complete runs of " + output.string() + " by " +
        std::to_string(new_fits) +
        " fits of the job's new values: only these are fitted (each run's samples and graph "
        "are computed again, the same bits), the fits it holds are kept");
  }
}

}  // namespace

std::string ggk_version_text() {
  return std::string(GGK_VERSION) + " (" + GGK_GIT_DESCRIBE + ")";
}

OpenedResults open_results(const Study& study, const RunOptions& options, bool under_mpi) {
  const JobSpec& job = study.job();
  const fs::path output = options.output.empty() ? job.output.file : options.output;
  if (options.runs && (options.runs->first < 0 || options.runs->first >= options.runs->last ||
                       options.runs->last > job.runs)) {
    throw UsageError("--runs " + std::to_string(options.runs->first) + ":" +
                     std::to_string(options.runs->last) + " is not a range of runs of job '" +
                     job.name + "', which has runs 0.." + std::to_string(job.runs - 1) +
                     " (A:B computes runs A..B-1, 0 <= A < B <= " + std::to_string(job.runs) + ")");
  }
  check_output_directory(output);
  OutputState state = output_state(output);  // refuse a device or FIFO before locking
  if (auto problem = results_extension_problem(output)) throw UsageError("output: " + *problem);
  if (state == OutputState::kFile && !options.resume && !options.overwrite) {
    throw UsageError(existing_output_refusal(study, output, options.output.empty()));
  }
  std::optional<ResultsTarget> target;  // before the lock and the stop signals: outlives both
  OutputLock lock = OutputLock::acquire(output);
  // Under the lock: what a dead ggk left is ours to clear, and the output is
  // looked at again (it may have appeared while we waited for nothing).
  const fs::path temporary = temporary_results_path(output);
  if (::unlink(temporary.c_str()) != 0 && errno != ENOENT) {
    throw UsageError("output " + output.string() + ": cannot remove the leftover " +
                     temporary.string() + ": " + std::strerror(errno));
  }
  state = output_state(output);
  // From here a stop signal removes the lock (and a .part) and prints how to go
  // on, while a resumed file is read back too; the runner's JobWriter takes the
  // handler over (stop_signals.hpp). Destroyed before the lock is released.
  const bool resuming = state == OutputState::kFile && options.resume;
  const GoOnText go_on = go_on_text(job, options, output, under_mpi);
  auto stop_signals = std::make_unique<StopSignals>(
      StopSignals::Mode::kStopInHandler,
      StopSignals::Report{output, resuming ? fs::path() : temporary, OutputLock::path_for(output),
                          go_on.published, go_on.unpublished});

  std::vector<std::vector<std::int32_t>> complete;  // per configuration
  std::vector<std::string> notes, info;
  std::optional<Hdf5File> file;
  std::optional<std::string> damage;  // why the file cannot be resumed in place
  bool crashes = false;               // reading the file crashes the HDF5 library: copy nothing
  const ReadingRoom room = ReadingRoom::for_files({output});
  if (resuming) {
    // Read whole in a child first (isolated_reading.hpp): a file whose damage
    // crashes HDF5 is never read here, where a crash would leave the lock.
    const ChildEnd vetted = read_whole_in_child(output);  // resume() reports its damage
    if (crashed(vetted) && room.user_limit_binds) {       // says nothing about the file
      throw UsageError("not enough memory to read " + output.string() + " back under " +
                       room.limit_words(output.string()) + ": reading it crashed (" +
                       ending_words(vetted) +
                       "), as HDF5 does when memory runs out; raise the limit (or lift it) and "
                       "resume again; the file is as it was");
    }
    if (crashed(vetted)) {
      crashes = true;
      damage = "reading it crashed the HDF5 library (" + ending_words(vetted) +
               "): an object header is damaged where HDF5 does not check";
    }
  }
  // The reading back (resume, salvage) in this process too bounds its address
  // space (reading_memory_cap.hpp): no computing thread exists yet.
  std::optional<ReadingMemoryCap> reading_cap;
  if (resuming) reading_cap.emplace(room);
  if (resuming && !crashes) {
    try {
      file.emplace(resume(study, options, output, complete, notes, info));
    } catch (const UsageError&) {
      throw;
    } catch (const std::runtime_error& e) {
      if (machine_error(e.what())) throw;
      damage = one_line(e.what());
      complete.clear();
    }
  }
  if (file) {
    target.emplace(output, fs::path(), std::move(lock));
  } else if (damage) {
    target.emplace(output, temporary, std::move(lock));  // removes the .part on failure
    file.emplace(salvage(study, options, output, temporary, *damage, crashes, complete, notes));
  } else {
    if (state == OutputState::kFile && !options.overwrite) {
      throw UsageError(
          "output " + output.string() +
          " exists: pass --resume to continue it, or --overwrite to replace it (deleting "
          "its complete runs)");
    }
    if (state == OutputState::kEmpty && options.resume) {
      notes.push_back(output.string() +
                      " is empty (a ggk killed while creating it): starting it afresh");
    }
    target.emplace(output, temporary, std::move(lock));  // removes the .part on failure
    file.emplace(create_new(study, options, temporary));
  }
  reading_cap.reset();
  OpenedResults opened{std::move(*target), std::move(stop_signals), std::move(*file), {}, 0,
                       std::move(notes),   std::move(info)};
  opened.file.set_gzip_level(job.output.compression);
  complete.resize(study.configurations.size());
  add_pending_units(study, options, complete, output, opened);
  return opened;
}

}  // namespace ggk::engine
