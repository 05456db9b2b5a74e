#include "engine/run/mpi_runner.hpp"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/job/job_error.hpp"
#include "engine/job/sweep.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/memory_check.hpp"
#include "engine/run/open_results.hpp"
#include "engine/run/progress.hpp"
#include "engine/store/run_store.hpp"
#include "engine/store/store_writer.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {

namespace {

using Clock = std::chrono::steady_clock;

// Message tags. Worker -> rank 0: ready (first request), result (a run's image,
// also a request for the next run), heartbeat (still computing), failed (an
// internal error; the worker stops). Rank 0 -> worker: assign (a run), stop.
enum Tag : int { kReady = 1, kResult = 2, kHeartbeat = 3, kFailed = 4, kAssign = 5, kStop = 6 };

constexpr auto kHeartbeatPeriod = std::chrono::milliseconds(250);

// Header of a result message, before the image bytes.
struct ResultHeader {
  std::int64_t run = 0;
  std::int64_t failed_fits = 0;
};

std::string processor_name() {
  char name[MPI_MAX_PROCESSOR_NAME];
  int length = 0;
  MPI_Get_processor_name(name, &length);
  return std::string(name, static_cast<std::size_t>(length));
}

// What went wrong on one rank: the exit status it calls for (0: nothing) and
// the message rank 0 prints.
struct Outcome {
  int status = 0;
  std::string message;
};

template <class Step>
Outcome attempt(Step&& step) {
  try {
    step();
    return {};
  } catch (const JobError& e) {
    return {2, e.what()};
  } catch (const UsageError& e) {
    return {2, e.what()};
  } catch (const std::exception& e) {
    return {1, std::string("internal error: ") + e.what()};
  }
}

// Collective: every rank learns the worst status; rank 0 learns the message of
// the lowest failing rank (prefixed with that rank when it is not rank 0) and
// prints it. Returns the worst status on every rank.
int agree(const Outcome& mine, int rank, int size) {
  int worst = 0;
  MPI_Allreduce(&mine.status, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (worst == 0) return 0;
  const int candidate = mine.status != 0 ? rank : size;
  int first = size;
  MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  std::string message = mine.message;
  if (first != 0) {
    if (rank == first) {
      MPI_Send(message.data(), static_cast<int>(message.size()), MPI_CHAR, 0, kFailed,
               MPI_COMM_WORLD);
    } else if (rank == 0) {
      MPI_Status status;
      MPI_Probe(first, kFailed, MPI_COMM_WORLD, &status);
      int count = 0;
      MPI_Get_count(&status, MPI_CHAR, &count);
      message.assign(static_cast<std::size_t>(count), '\0');
      MPI_Recv(message.data(), count, MPI_CHAR, first, kFailed, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      message =
          "rank " + std::to_string(first) + " (" + std::to_string(size) + " ranks): " + message;
    }
  }
  if (rank == 0) std::fprintf(stderr, "ggk: error: %s\n", message.c_str());
  return worst;
}

// The job as rank 0 read it: its text and its input files, which every rank must
// have read identically.
std::string fingerprint(const JobSpec& job) {
  std::string text = job.source_text;
  for (const JobInput& input : job.inputs) text += '\0' + input.key + '\0' + input.text;
  return text;
}

Outcome check_same_job(const JobSpec& job, int rank) {
  std::string reference = rank == 0 ? fingerprint(job) : std::string();
  auto length = static_cast<std::uint64_t>(reference.size());
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  reference.resize(length);
  MPI_Bcast(reference.data(), static_cast<int>(length), MPI_CHAR, 0, MPI_COMM_WORLD);
  if (rank == 0 || reference == fingerprint(job)) return {};
  return {2, "on " + processor_name() + ", " + job.source_file.string() +
                 " or the files it names differ from what rank 0 read; every rank must read "
                 "the same job (a shared file system)"};
}

// --------------------------------------------------------------- signals
// Rank 0 reports the runs in flight when the launcher stops the job (mpirun
// sends SIGTERM to every rank when one dies). The handler only sets a flag; the
// coordinator's loop, which polls every few milliseconds, prints and exits.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int signal) {
  g_stop_signal = signal;
}

// --------------------------------------------------------------- worker
int work(const JobSpec& job) {
  MPI_Send(nullptr, 0, MPI_BYTE, 0, kReady, MPI_COMM_WORLD);
  for (;;) {
    MPI_Status status;
    std::int64_t run = -1;
    MPI_Recv(&run, 1, MPI_INT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
    if (status.MPI_TAG == kStop) return 0;
    // Compute on oneTBB's threads; this (the MPI) thread says it is alive.
    std::future<RunRecord> computing = std::async(std::launch::async, [&job, run] {
      return compute_run(job, static_cast<std::int32_t>(run));
    });
    while (computing.wait_for(kHeartbeatPeriod) != std::future_status::ready) {
      MPI_Send(nullptr, 0, MPI_BYTE, 0, kHeartbeat, MPI_COMM_WORLD);
    }
    std::vector<unsigned char> message;
    try {
      const RunRecord record = computing.get();
      const ResultHeader header{run, failed_fits_of(record)};
      const std::vector<unsigned char> image = run_image(job, record);
      message.resize(sizeof header + image.size());
      std::memcpy(message.data(), &header, sizeof header);
      std::memcpy(message.data() + sizeof header, image.data(), image.size());
      if (message.size() > static_cast<std::size_t>(INT32_MAX)) {
        throw std::runtime_error("run " + std::to_string(run) + " is " +
                                 std::to_string(message.size()) +
                                 " bytes, over MPI's 2 GiB message limit");
      }
    } catch (const std::exception& e) {
      const std::string text =
          "run " + std::to_string(run) + " on " + processor_name() + ": " + e.what();
      MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, kFailed, MPI_COMM_WORLD);
      return 1;
    }
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, kResult,
             MPI_COMM_WORLD);
  }
}

// --------------------------------------------------------------- rank 0
class Coordinator {
 public:
  Coordinator(const JobSpec& job, const MpiRunOptions& options, int size, OpenedResults opened)
      : job_(job),
        options_(options),
        size_(size),
        target_(std::move(opened.target)),
        skipped_(opened.skipped),
        pending_(opened.pending.begin(), opened.pending.end()),
        total_(static_cast<std::int32_t>(opened.pending.size())),
        writer_(std::move(opened.file), StoreWriter::kDefaultQueueCapacity,
                StoreWriter::WhenIdle::kCloseForReaders) {}

  // Returns the exit status; fills summary on success.
  int run(RunSummary& summary);

 private:
  std::optional<std::int32_t> take_run() {
    std::lock_guard lock(mutex_);
    if (pending_.empty() || !failure_.empty()) return std::nullopt;
    const std::int32_t run = pending_.front();
    pending_.pop_front();
    return run;
  }
  void fail(std::string message) {
    std::lock_guard lock(mutex_);
    if (failure_.empty()) failure_ = std::move(message);
    pending_.clear();
  }
  bool failed() {
    std::lock_guard lock(mutex_);
    return !failure_.empty();
  }
  void compute_locally();
  void assign_or_stop(int rank);
  void receive(const MPI_Status& status);
  [[noreturn]] void stop_now(const std::string& why, int exit_status);
  std::string runs_in_flight() const;

  const JobSpec& job_;
  const MpiRunOptions& options_;
  const int size_;
  ResultsTarget target_;  // before writer_: the lock outlives the file
  const std::int32_t skipped_;

  std::mutex mutex_;  // pending_, failure_, local_run_
  std::deque<std::int32_t> pending_;
  std::string failure_;
  std::atomic<bool> local_finished_{false};

  const std::int32_t total_;
  std::atomic<std::int32_t> written_{0};
  std::atomic<std::int64_t> failed_fits_{0};
  StoreWriter writer_;
  std::optional<Progress> progress_;

  struct Held {
    std::int32_t run = -1;  // -1: none
    Clock::time_point last_heard;
  };
  std::map<int, Held> held_;  // worker rank -> its run (main thread only)
  int active_workers_ = 0;
};

void Coordinator::compute_locally() {
  while (const std::optional<std::int32_t> run = take_run()) {
    try {
      auto record = std::make_shared<const RunRecord>(compute_run(job_, *run));
      failed_fits_.fetch_add(failed_fits_of(*record));
      writer_.submit([this, record](Hdf5File& file) {
        write_run(file, job_, *record);
        target_.publish(file);
        written_.fetch_add(1);
        progress_->run_done();
      });
    } catch (const std::exception& e) {
      fail("run " + std::to_string(*run) + " on rank 0: " + e.what());
    }
  }
  local_finished_ = true;
}

void Coordinator::assign_or_stop(int rank) {
  if (const std::optional<std::int32_t> run = take_run()) {
    const std::int64_t value = *run;
    held_[rank] = {*run, Clock::now()};
    MPI_Send(&value, 1, MPI_INT64_T, rank, kAssign, MPI_COMM_WORLD);
  } else {
    const std::int64_t none = -1;
    held_.erase(rank);
    --active_workers_;
    MPI_Send(&none, 1, MPI_INT64_T, rank, kStop, MPI_COMM_WORLD);
  }
}

void Coordinator::receive(const MPI_Status& status) {
  const int rank = status.MPI_SOURCE;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  auto bytes = std::make_shared<std::vector<unsigned char>>(static_cast<std::size_t>(count));
  MPI_Recv(bytes->data(), count, MPI_BYTE, rank, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  switch (status.MPI_TAG) {
    case kHeartbeat:
      held_[rank].last_heard = Clock::now();
      return;
    case kReady:
      assign_or_stop(rank);
      return;
    case kResult: {
      ResultHeader header;
      if (bytes->size() < sizeof header) throw std::runtime_error("short result message");
      std::memcpy(&header, bytes->data(), sizeof header);
      failed_fits_.fetch_add(header.failed_fits);
      const auto run = static_cast<std::int32_t>(header.run);
      writer_.submit([this, bytes, run](Hdf5File& file) {
        write_run_image(file, job_, run,
                        std::span<const unsigned char>(bytes->data() + sizeof(ResultHeader),
                                                       bytes->size() - sizeof(ResultHeader)));
        target_.publish(file);
        written_.fetch_add(1);
        progress_->run_done();
      });
      assign_or_stop(rank);
      return;
    }
    case kFailed:
      fail("rank " + std::to_string(rank) + ": " +
           std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
      held_.erase(rank);
      --active_workers_;  // a failed worker stops by itself
      return;
    default:
      throw std::runtime_error("unexpected MPI message tag " + std::to_string(status.MPI_TAG) +
                               " from rank " + std::to_string(rank));
  }
}

std::string Coordinator::runs_in_flight() const {
  std::string text;
  const auto now = Clock::now();
  for (const auto& [rank, held] : held_) {
    if (held.run < 0) continue;
    const double silent = std::chrono::duration<double>(now - held.last_heard).count();
    char line[160];
    std::snprintf(line, sizeof line, "\n  run %d on rank %d (silent for %.1f s)", held.run, rank,
                  silent);
    text += line;
  }
  return text.empty() ? " none" : text;
}

void Coordinator::stop_now(const std::string& why, int exit_status) {
  // Runs already written are complete (each is committed whole); the one the
  // writer may be writing is in its staging group, which --resume discards.
  std::fprintf(stderr,
               "\nggk: error: %s\nggk: runs in flight:%s\nggk: %d of %d runs of this session were "
               "written to %s and are complete; finish the job with `ggk run %s --resume -o %s` "
               "(any number of ranks, or none)\n",
               why.c_str(), runs_in_flight().c_str(), written_.load(), total_,
               target_.output().string().c_str(), job_.source_file.string().c_str(),
               target_.output().string().c_str());
  std::fflush(stderr);
  target_.release_lock();  // a resume on another node must not find it locked
  std::_Exit(exit_status);
}

int Coordinator::run(RunSummary& summary) {
  const auto started = Clock::now();
  const auto fits_per_run = static_cast<std::int32_t>(expand_sweep(job_).size());
  progress_.emplace(total_, fits_per_run, options_.run.quiet);
  active_workers_ = size_ - 1;
  std::signal(SIGTERM, on_stop_signal);
  std::signal(SIGINT, on_stop_signal);

  std::thread local([this] { compute_locally(); });
  while (active_workers_ > 0) {
    if (g_stop_signal != 0) {
      local.detach();
      stop_now(std::string("stopped by ") + (g_stop_signal == SIGINT ? "SIGINT" : "SIGTERM") +
                   " (under mpirun: a rank died or was killed, and mpirun stopped the others; "
                   "its message names the rank)",
               128 + g_stop_signal);
    }
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
    if (arrived) {
      receive(status);
      continue;
    }
    const auto now = Clock::now();
    for (const auto& [rank, held] : held_) {
      const double silent = std::chrono::duration<double>(now - held.last_heard).count();
      if (held.run >= 0 && silent > options_.rank_timeout_seconds) {
        local.detach();
        stop_now("rank " + std::to_string(rank) + " stopped answering (silent for " +
                     std::to_string(static_cast<int>(silent)) + " s) while holding run " +
                     std::to_string(held.run),
                 1);
      }
    }
    if (writer_.failed()) {
      local.detach();
      try {
        writer_.wait();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "ggk: error: %s\n", e.what());
      }
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // The local computation ends with the pending runs; a signal still stops it.
  while (!local_finished_) {
    if (g_stop_signal != 0) {
      local.detach();
      stop_now("stopped by a signal", 128 + g_stop_signal);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  local.join();
  writer_.wait();  // rethrows a write failure
  progress_.reset();
  if (failed()) {
    std::fprintf(stderr,
                 "ggk: error: %s\nggk: the runs written are complete; fix the cause and "
                 "finish with --resume\n",
                 failure_.c_str());
    return 1;
  }
  writer_.submit([this](Hdf5File& file) {
    write_summary(file, job_);
    target_.publish(file);
  });
  writer_.close();
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGINT, SIG_DFL);

  summary.output = target_.output();
  summary.runs_computed = total_;
  summary.runs_skipped = skipped_;
  summary.fits = static_cast<std::int64_t>(total_) * fits_per_run;
  summary.failed_fits = failed_fits_.load();
  summary.seconds = std::chrono::duration<double>(Clock::now() - started).count();
  return 0;
}

}  // namespace

bool launched_by_mpi() {
  for (const char* variable :
       {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS"}) {
    if (std::getenv(variable) != nullptr) return true;
  }
  return false;
}

MpiSession::MpiSession(int& argc, char**& argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  MPI_Finalize();
}

int run_job_over_mpi(const MpiSession& session, const std::filesystem::path& job_path,
                     const MpiRunOptions& options) {
  const int rank = session.rank(), size = session.size();
  std::optional<JobSpec> job;
  std::optional<ComputeThreads> threads;
  // Rank 0 checks the output's folder; the others only read the job.
  JobLoadOptions load = options.load;
  if (rank != 0) load.check_output = false;
  if (const int status = agree(attempt([&] {
                                 job.emplace(load_job_file(job_path, task_tables(), load));
                                 threads.emplace(options.run.threads);
                               }),
                               rank, size)) {
    return status;
  }
  if (const int status = agree(check_same_job(*job, rank), rank, size)) return status;

  std::optional<OpenedResults> opened;
  if (rank == 0) {
    const Outcome outcome = attempt([&] {
      check_memory(*job, options.run);  // before the output is created or touched
      opened.emplace(open_results(*job, options.run));
    });
    if (const int status = agree(outcome, rank, size)) return status;
  } else if (const int status = agree({}, rank, size)) {
    return status;
  }

  if (rank != 0) return work(*job);

  RunSummary summary;
  int status = 0;
  const Outcome outcome = attempt([&] {
    Coordinator coordinator(*job, options, size, std::move(*opened));
    status = coordinator.run(summary);
  });
  if (outcome.status != 0) {
    std::fprintf(stderr, "ggk: error: %s\n", outcome.message.c_str());
    MPI_Abort(MPI_COMM_WORLD, outcome.status);
  }
  if (status == 0) print_run_summary(*job, summary);
  return status;
}

}  // namespace ggk::engine
