#include "engine/run/mpi_runner.hpp"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
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
#include <set>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "engine/job/job_error.hpp"
#include "engine/job/sweep.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/adaptive_runner.hpp"
#include "engine/run/job_writer.hpp"
#include "engine/run/memory_check.hpp"
#include "engine/run/open_results.hpp"
#include "engine/run/run_pieces.hpp"
#include "engine/run/stop_signals.hpp"
#include "engine/store/process_state.hpp"
#include "engine/store/run_extension.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/fit_count.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {

namespace {

using Clock = std::chrono::steady_clock;

// Message tags. Worker -> rank 0: ready (first request), result (a run's image,
// also a request for the next run), heartbeat (still computing), failed (an
// internal error; the worker stops), stopped (by a signal; the worker exits).
// Rank 0 -> worker: assign (a run; a unit's points follow as assign_points), stop.
enum Tag : int {
  kReady = 1,
  kResult = 2,
  kHeartbeat = 3,
  kFailed = 4,
  kAssign = 5,
  kStop = 6,
  kStopped = 7,      // worker -> rank 0: a stop signal arrived (its number); the worker exits
  kAssignPoints = 8  // rank 0 -> worker, right after an assign of some points: the points
};

constexpr auto kHeartbeatPeriod = std::chrono::milliseconds(250);
// How often a worker looks for a stop signal, and how long rank 0 waits for
// every worker to report one (mpirun sends SIGKILL 1 s after its SIGTERM:
// odls_base_sigkill_timeout).
constexpr auto kStopPoll = std::chrono::milliseconds(10);
constexpr auto kStopReportWait = std::chrono::milliseconds(600);
// How much longer rank 0 waits for a worker of its own host that has not
// reported but whose process still runs (process_alive): one slow to notice its
// signal on a loaded machine, not a dead one.
constexpr auto kSlowWorkerWait = std::chrono::seconds(10);
// How long a stopped worker waits for rank 0 to report before it exits (under
// mpirun, its SIGKILL comes first).
constexpr auto kStopAckWait = std::chrono::milliseconds(2000);

// Header of a result message, before the image bytes.
struct ResultHeader {
  std::int64_t run = 0;
  std::int64_t configuration = 0;
  std::int64_t failed_fits = 0;
  std::int64_t extension = 0;  // 1: the image extends a stored run (RunRecord::extension)
  std::int64_t fits_done = 0;  // the worker's fits ended so far (tasks/fit_count.hpp)
};

// A unit of work (study.hpp) as the one int64 an assignment sends, and back;
// a unit of some points only (WorkUnit::points) sets kWithPoints, and its
// points follow in a kAssignPoints message; one that extends a stored run
// (WorkUnit::extends) also sets kExtends.
constexpr std::int64_t kWithPoints = std::int64_t{1} << 62;
constexpr std::int64_t kExtends = std::int64_t{1} << 61;
std::int64_t encode(const WorkUnit& unit) {
  return (static_cast<std::int64_t>(unit.configuration) << 32) |
         static_cast<std::int64_t>(static_cast<std::uint32_t>(unit.run)) |
         (unit.points.empty() ? 0 : kWithPoints) | (unit.extends ? kExtends : 0);
}
WorkUnit decode(std::int64_t value) {
  WorkUnit unit;
  unit.configuration = static_cast<std::int32_t>((value & ~(kWithPoints | kExtends)) >> 32);
  unit.run = static_cast<std::int32_t>(static_cast<std::uint32_t>(value & 0xffffffff));
  unit.extends = (value & kExtends) != 0;
  return unit;
}

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

// --------------------------------------------------------------- worker
// A worker stopped by a signal (mpirun sends SIGTERM to every rank on a Ctrl-C,
// a scheduler to every process) says so to rank 0, so that rank 0 knows it was
// stopped and did not die, and exits with 128 + signal once rank 0 has reported
// (its kStop) or after kStopAckWait: mpirun ends the whole job as soon as one
// rank exits, and rank 0 must have printed and released the lock by then.
// `receiving`: the worker's posted receive of its next run, if any.
[[noreturn]] void report_stop_and_exit(int signal, MPI_Request* receiving) {
  MPI_Send(&signal, 1, MPI_INT, 0, kStopped, MPI_COMM_WORLD);
  bool acknowledged = false;
  if (receiving != nullptr) {
    MPI_Status status;
    MPI_Cancel(receiving);
    MPI_Wait(receiving, &status);
    int cancelled = 0;
    MPI_Test_cancelled(&status, &cancelled);
    acknowledged = !cancelled && status.MPI_TAG == kStop;
  }
  for (const auto deadline = Clock::now() + kStopAckWait;
       !acknowledged && Clock::now() < deadline;) {
    int arrived = 0;
    MPI_Iprobe(0, kStop, MPI_COMM_WORLD, &arrived, MPI_STATUS_IGNORE);
    acknowledged = arrived != 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  std::_Exit(128 + signal);
}

int work(const Study& study) {
  const StopSignals stop_signals(StopSignals::Mode::kRecord);
  // The first request names the worker's process: its pid and host.
  const std::string hello = std::to_string(getpid()) + " " + processor_name();
  MPI_Send(hello.data(), static_cast<int>(hello.size()), MPI_CHAR, 0, kReady, MPI_COMM_WORLD);
  for (;;) {
    MPI_Status status;
    std::int64_t run = -1;
    MPI_Request request;
    MPI_Irecv(&run, 1, MPI_INT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &request);
    for (int arrived = 0;;) {
      MPI_Test(&request, &arrived, &status);
      if (arrived) break;
      if (const int signal = stop_signals.received()) report_stop_and_exit(signal, &request);
      std::this_thread::sleep_for(kStopPoll);
    }
    if (status.MPI_TAG == kStop) return 0;
    // Compute on oneTBB's threads; this (the MPI) thread says it is alive.
    WorkUnit unit = decode(run);
    if ((run & kWithPoints) != 0) {  // sent right after the assignment
      MPI_Status points_status;
      MPI_Probe(0, kAssignPoints, MPI_COMM_WORLD, &points_status);
      int count = 0;
      MPI_Get_count(&points_status, MPI_INT32_T, &count);
      unit.points.resize(static_cast<std::size_t>(count));
      MPI_Recv(unit.points.data(), count, MPI_INT32_T, 0, kAssignPoints, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
    }
    const JobSpec& job = study.configurations.at(unit.configuration).job;
    std::future<RunRecord> computing =
        std::async(std::launch::async, [&study, unit] { return compute_unit(study, unit); });
    auto last_heartbeat = Clock::now();
    while (computing.wait_for(kStopPoll) != std::future_status::ready) {
      if (const int signal = stop_signals.received()) report_stop_and_exit(signal, nullptr);
      if (Clock::now() - last_heartbeat >= kHeartbeatPeriod) {
        // With the fits this worker has ended so far: rank 0's progress counts them.
        const std::int64_t fits = fits_done();
        MPI_Send(&fits, 1, MPI_INT64_T, 0, kHeartbeat, MPI_COMM_WORLD);
        last_heartbeat = Clock::now();
      }
    }
    std::vector<unsigned char> message;
    try {
      const RunRecord record = computing.get();
      const ResultHeader header{unit.run, unit.configuration, failed_fits_of(record),
                                record.extension ? 1 : 0, fits_done()};
      const std::vector<unsigned char> image = run_image(job, record);
      message.resize(sizeof header + image.size());
      std::memcpy(message.data(), &header, sizeof header);
      std::memcpy(message.data() + sizeof header, image.data(), image.size());
      if (message.size() > static_cast<std::size_t>(INT32_MAX)) {
        throw std::runtime_error(unit_words(study, unit) + " is " + std::to_string(message.size()) +
                                 " bytes, over MPI's 2 GiB message limit");
      }
    } catch (const std::exception& e) {
      const std::string text =
          unit_words(study, unit) + " on " + processor_name() + ": " + e.what();
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
  // An adaptive study's units are handed out look by look (AdaptiveLooks): the
  // queue starts empty and is refilled when every run of a look is written.
  Coordinator(const Study& study, const MpiRunOptions& options, int size, OpenedResults opened)
      : study_(study),
        options_(options),
        size_(size),
        skipped_(opened.skipped),
        looks_(study.job().adaptive
                   ? std::optional<AdaptiveLooks>(std::in_place, study, options.run)
                   : std::nullopt),
        pending_(looks_ ? std::deque<WorkUnit>()
                        : std::deque<WorkUnit>(opened.pending.begin(), opened.pending.end())),
        total_(static_cast<std::int32_t>(pending_.size())),
        writer_(study, options.run, std::move(opened), total_, StopSignals::Mode::kRecord) {
    const std::deque<WorkUnit> opened_units = std::exchange(pending_, {});
    queue(std::vector<WorkUnit>(opened_units.begin(), opened_units.end()));
  }

  // Returns the exit status; fills summary on success.
  int run(RunSummary& summary);
  // The workers that reported a stop signal wait for this (a kStop) to exit.
  void release_stopped_workers();

 private:
  // Queues `units`, those of their last round over the ranks in pieces
  // (run_pieces.hpp), whose run is written once every piece has come (deliver).
  void queue(std::span<const WorkUnit> units) {
    PiecedUnits pieced = split_tail_runs(study_, units, size_);
    {
      std::lock_guard lock(mutex_);
      for (const auto& [run, count] : pieced.pieces) assemblies_[run].expected = count;
      runs_in_pieces_ += static_cast<std::int32_t>(pieced.pieces.size());
      pending_.insert(pending_.end(), pieced.units.begin(), pieced.units.end());
    }
    more_runs_.notify_all();
  }
  // A piece of a run computed in pieces, from any rank: the run is committed with
  // its last piece. False when the run is not computed in pieces.
  bool deliver(std::int32_t configuration, std::int32_t run, RunPiece piece) {
    std::vector<RunPiece> whole;
    {
      std::lock_guard lock(mutex_);
      const auto found = assemblies_.find({configuration, run});
      if (found == assemblies_.end()) return false;
      found->second.pieces.push_back(std::move(piece));
      if (static_cast<std::int32_t>(found->second.pieces.size()) < found->second.expected) {
        return true;
      }
      whole = std::move(found->second.pieces);
      assemblies_.erase(found);
    }
    writer_.commit_pieces(configuration, run, std::move(whole));
    return true;
  }
  // The next queued unit, none once the job failed or stops; mutex_ held.
  std::optional<WorkUnit> pop_run_locked() {
    if (pending_.empty() || !failure_.empty() || stopping_) return std::nullopt;
    const WorkUnit run = pending_.front();
    pending_.pop_front();
    return run;
  }
  std::optional<WorkUnit> take_run() {
    std::lock_guard lock(mutex_);
    return pop_run_locked();
  }
  void fail(std::string message) {
    {
      std::lock_guard lock(mutex_);
      if (failure_.empty()) failure_ = std::move(message);
      pending_.clear();
    }
    more_runs_.notify_all();
  }
  bool failed() {
    std::lock_guard lock(mutex_);
    return !failure_.empty();
  }
  // A stop signal seen here or reported by a worker: hand out no more runs.
  void start_stopping(int signal) {
    if (stop_signal_ != 0) return;
    stop_signal_ = signal;
    stop_deadline_ = Clock::now() + kStopReportWait;
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    more_runs_.notify_all();
  }
  // Nothing would be lost by going on: every run is written or queued (and an
  // adaptive study's rule asks for no more).
  bool all_runs_done() {
    std::lock_guard lock(mutex_);
    return pending_.empty() && local_finished_ && (!looks_ || looks_done_) &&
           std::none_of(held_.begin(), held_.end(),
                        [](const auto& h) { return h.second.run >= 0; });
  }
  // An adaptive study may yet hand out runs: its rule is not done, and nothing
  // failed or stopped.
  bool more_looks_may_come() {
    std::lock_guard lock(mutex_);
    return looks_ && !looks_done_ && failure_.empty() && !stopping_;
  }
  void compute_locally();
  // The message loop of rank 0 until every worker and its own compute thread are
  // done: assigns runs, receives results, watches for stops and silent ranks.
  void coordinate();
  void assign_or_stop(int rank);
  // Tells a worker to exit (kStop): it gets no more runs.
  void stop_worker(int rank);
  // An adaptive study between looks: when no run is queued, computed or held,
  // every run of the look is written, and the next look's units are queued and
  // handed to the waiting ranks (or, the rule done, the waiting ranks stopped).
  void advance_look_when_idle();
  // Tells the ranks waiting for a look's runs to stop.
  void release_waiting_workers();
  void receive(const MPI_Status& status);
  void stop_for_signal();
  // The active workers of this host whose process is gone (dead or a zombie).
  std::set<int> gone_workers_on_this_host() const;
  // "rank 1 (holding run 3), rank 2": ranks with the runs they hold.
  std::string ranks_words(const std::set<int>& ranks) const;
  [[noreturn]] void stop_now(const std::string& headline, int exit_status);
  void report_stop(const std::string& headline);
  std::string runs_in_flight() const;

  const Study& study_;
  const MpiRunOptions& options_;
  const int size_;
  const std::int32_t skipped_;

  std::optional<AdaptiveLooks> looks_;  // an adaptive study's looks (main thread only)
  std::mutex mutex_;                    // pending_, assemblies_, failure_, stopping_, looks_done_
  std::condition_variable more_runs_;   // pending_ refilled, or no run will come
  std::deque<WorkUnit> pending_;
  // The runs computed in pieces not yet committed: (configuration, run) -> the
  // pieces come so far and how many it has.
  struct Assembly {
    std::int32_t expected = 0;
    std::vector<RunPiece> pieces;
  };
  std::map<std::pair<std::int32_t, std::int32_t>, Assembly> assemblies_;
  std::int32_t runs_in_pieces_ = 0;
  std::string failure_;
  bool stopping_ = false;
  bool looks_done_ = false;  // an adaptive study's rule asks for no more runs
  std::set<int> waiting_;    // ranks waiting for the next look's runs
  std::atomic<bool> local_finished_{false};
  std::atomic<std::int64_t> local_run_{-1};  // the unit rank 0 computes (encode), -1: none

  std::int32_t total_;  // the runs of this session handed out so far (all, unless adaptive)
  std::atomic<std::int64_t> failed_fits_{0};
  JobWriter writer_;

  struct Held {
    std::int32_t run = -1;  // -1: none
    std::int32_t configuration = 0;
    Clock::time_point last_heard;
  };
  std::map<int, Held> held_;  // worker rank -> its run
  // Worker rank -> the fits it has said it ended (heartbeats and results carry
  // its running count): the progress display counts the fits of every rank.
  std::map<int, std::int64_t> worker_fits_;
  void count_worker_fits(int rank, std::int64_t fits) {
    std::int64_t& counted = worker_fits_[rank];
    if (fits > counted) writer_.add_remote_fits(fits - counted);
    counted = std::max(counted, fits);
  }
  std::set<int> active_;   // workers not yet told to stop, failed or stopped by a signal
  std::set<int> stopped_;  // workers that reported a stop signal
  struct Process {
    pid_t pid = 0;
    std::string host;
  };
  std::map<int, Process> processes_;  // worker rank -> its process (its first message)
  const std::string host_ = processor_name();
  int stop_signal_ = 0;
  bool stop_reported_ = false;  // the stop's report is printed; the job stops
  Clock::time_point stop_deadline_;
};

void Coordinator::compute_locally() {
  for (;;) {
    std::optional<WorkUnit> run;
    {
      // Taken with local_run_ set under the lock: advance_look_when_idle never
      // sees a run in neither the queue nor local_run_.
      std::unique_lock lock(mutex_);
      if (looks_) {
        more_runs_.wait(lock, [this] {
          return !pending_.empty() || looks_done_ || stopping_ || !failure_.empty();
        });
      }
      run = pop_run_locked();
      if (!run) break;
      local_run_ = encode(*run);
    }
    try {
      auto record = std::make_shared<const RunRecord>(compute_unit(study_, *run));
      failed_fits_.fetch_add(failed_fits_of(*record));
      if (!deliver(run->configuration, run->run, {record, nullptr, 0, record->extension})) {
        writer_.commit(std::move(record));
      }
    } catch (const std::exception& e) {
      fail(unit_words(study_, *run) + " on rank 0: " + e.what());
    }
    local_run_ = -1;
  }
  local_finished_ = true;
}

void Coordinator::assign_or_stop(int rank) {
  if (const std::optional<WorkUnit> run = take_run()) {
    const std::int64_t value = encode(*run);
    held_[rank] = {run->run, run->configuration, Clock::now()};
    MPI_Send(&value, 1, MPI_INT64_T, rank, kAssign, MPI_COMM_WORLD);
    if (!run->points.empty()) {
      MPI_Send(run->points.data(), static_cast<int>(run->points.size()), MPI_INT32_T, rank,
               kAssignPoints, MPI_COMM_WORLD);
    }
  } else if (more_looks_may_come()) {
    waiting_.insert(rank);  // answered by the next look (advance_look_when_idle)
  } else {
    stop_worker(rank);
  }
}

void Coordinator::stop_worker(int rank) {
  const std::int64_t none = -1;
  held_.erase(rank);
  active_.erase(rank);
  MPI_Send(&none, 1, MPI_INT64_T, rank, kStop, MPI_COMM_WORLD);
}

void Coordinator::advance_look_when_idle() {
  if (!more_looks_may_come()) {
    release_waiting_workers();
    return;
  }
  {
    std::lock_guard lock(mutex_);
    if (!pending_.empty() || local_run_ >= 0) return;
  }
  if (std::any_of(held_.begin(), held_.end(), [](const auto& h) { return h.second.run >= 0; })) {
    return;
  }
  writer_.wait();  // the look's runs are in the file the rule decides on
  const std::vector<WorkUnit> look = looks_->next_look(writer_);
  total_ += static_cast<std::int32_t>(look.size());
  if (look.empty()) {
    std::lock_guard lock(mutex_);
    looks_done_ = true;
  }
  queue(look);
  for (const int rank : std::exchange(waiting_, {})) assign_or_stop(rank);
}

void Coordinator::release_waiting_workers() {
  for (const int rank : std::exchange(waiting_, {})) stop_worker(rank);
}

void Coordinator::receive(const MPI_Status& status) {
  const int rank = status.MPI_SOURCE;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  auto bytes = std::make_shared<std::vector<unsigned char>>(static_cast<std::size_t>(count));
  MPI_Recv(bytes->data(), count, MPI_BYTE, rank, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  switch (status.MPI_TAG) {
    case kHeartbeat: {
      held_[rank].last_heard = Clock::now();
      std::int64_t fits = 0;
      if (bytes->size() == sizeof fits) {
        std::memcpy(&fits, bytes->data(), sizeof fits);
        count_worker_fits(rank, fits);
      }
      return;
    }
    case kReady: {
      const std::string hello(reinterpret_cast<const char*>(bytes->data()), bytes->size());
      const std::string::size_type space = hello.find(' ');
      if (space != std::string::npos) {
        processes_[rank] = {static_cast<pid_t>(std::stol(hello.substr(0, space))),
                            hello.substr(space + 1)};
      }
      assign_or_stop(rank);
      return;
    }
    case kResult: {
      ResultHeader header;
      if (bytes->size() < sizeof header) throw std::runtime_error("short result message");
      std::memcpy(&header, bytes->data(), sizeof header);
      failed_fits_.fetch_add(header.failed_fits);
      count_worker_fits(rank, header.fits_done);
      const auto configuration = static_cast<std::int32_t>(header.configuration);
      const auto run = static_cast<std::int32_t>(header.run);
      if (!deliver(configuration, run,
                   {nullptr, bytes, sizeof(ResultHeader), header.extension != 0})) {
        writer_.commit_image(configuration, run, std::move(bytes), sizeof(ResultHeader),
                             header.extension != 0);
      }
      held_[rank].run = -1;
      assign_or_stop(rank);
      return;
    }
    case kStopped: {
      int signal = SIGTERM;
      if (bytes->size() == sizeof signal) std::memcpy(&signal, bytes->data(), sizeof signal);
      stopped_.insert(rank);
      active_.erase(rank);  // it exits by itself; what it held is in flight
      start_stopping(signal);
      return;
    }
    case kFailed: {
      fail("rank " + std::to_string(rank) + ": " +
           std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
      held_.erase(rank);
      active_.erase(rank);  // a failed worker stops by itself
      return;
    }
    default:
      throw std::runtime_error("unexpected MPI message tag " + std::to_string(status.MPI_TAG) +
                               " from rank " + std::to_string(rank));
  }
}

std::string Coordinator::runs_in_flight() const {
  std::string text;
  if (const std::int64_t run = local_run_; run >= 0) {
    text += "\n  " + unit_words(study_, decode(run)) + " on rank 0";
  }
  const auto now = Clock::now();
  for (const auto& [rank, held] : held_) {
    if (held.run < 0) continue;
    const double silent = std::chrono::duration<double>(now - held.last_heard).count();
    char line[160];
    std::snprintf(line, sizeof line, "\n  %s on rank %d (silent for %.1f s)",
                  unit_words(study_, {held.configuration, held.run}).c_str(), rank, silent);
    text += line;
  }
  return text.empty() ? " none" : text;
}

void Coordinator::report_stop(const std::string& headline) {
  // Runs already written are complete (each is committed whole); the one the
  // writer may be writing is in its staging group, which --resume discards.
  char written[160];
  std::snprintf(written, sizeof written, "ggk: %d of %d runs of this session were written\n",
                writer_.written(), total_);
  writer_.stop_signals().report(headline, "ggk: runs in flight, computed again by that command:" +
                                              runs_in_flight() + "\n" + written);
  std::fflush(stderr);
}

void Coordinator::stop_now(const std::string& headline, int exit_status) {
  report_stop(headline);
  release_stopped_workers();
  std::_Exit(exit_status);
}

void Coordinator::release_stopped_workers() {
  const std::int64_t none = -1;
  for (const int rank : stopped_) MPI_Send(&none, 1, MPI_INT64_T, rank, kStop, MPI_COMM_WORLD);
  stopped_.clear();
}

// A stop signal here or on a worker. Reported at once (mpirun sends SIGKILL 1 s
// after its SIGTERM, sooner than a loaded machine may let a report wait): the
// signal, the command that finishes the job and the runs in flight. Then waits
// (briefly) until every worker still computing has reported its own signal:
// then the job was interrupted (a Ctrl-C, a scheduler), exit 128 + signal. A
// worker silent past the wait died before the signal (mpirun stops the others
// when one dies): it is named with its run, exit 1; unless it runs on this host
// and its process is still alive (process_alive): then it is slow, not dead, and
// rank 0 waits for its report up to kSlowWorkerWait longer. When nothing is lost (every
// run written or queued) at the signal, the job ends normally instead.
std::set<int> Coordinator::gone_workers_on_this_host() const {
  std::set<int> gone;
  for (const int rank : active_) {
    const auto process = processes_.find(rank);
    if (process != processes_.end() && process->second.host == host_ &&
        !process_alive(process->second.pid)) {
      gone.insert(rank);
    }
  }
  return gone;
}

std::string Coordinator::ranks_words(const std::set<int>& ranks) const {
  std::string words;
  for (const int rank : ranks) {
    const auto held = held_.find(rank);
    words += (words.empty() ? "" : ", ") + std::string("rank ") + std::to_string(rank) +
             (held != held_.end() && held->second.run >= 0
                  ? " (holding " +
                        unit_words(study_, {held->second.configuration, held->second.run}) + ")"
                  : std::string());
  }
  return words;
}

void Coordinator::stop_for_signal() {
  if (!stop_reported_) {
    stop_reported_ = true;
    // A worker of this host whose process is already gone died before the
    // signal, which is then mpirun's answer to its death: named at once, since
    // mpirun's SIGKILL may end this process before the wait below does (stop
    // 41's campaign, F11: a killed rank 1 was reported as "stopped by SIGTERM").
    if (const std::string dead = ranks_words(gone_workers_on_this_host()); !dead.empty()) {
      report_stop(std::string("error: ") + dead + " died or was killed, and mpirun then sent " +
                  StopSignals::name_of(stop_signal_) + " to every rank");
      release_stopped_workers();
      std::_Exit(1);
    }
    report_stop(std::string(StopSignals::headline_of(stop_signal_)) +
                (stop_signal_ == SIGTERM ? " (mpirun's, on a Ctrl-C, or a scheduler's)" : ""));
  }
  if (!active_.empty() && Clock::now() < stop_deadline_) return;
  // A worker of this host whose process still runs has not died: it is slow to
  // see its signal (a loaded machine). Wait for it, up to kSlowWorkerWait (under
  // mpirun's own stop, mpirun's SIGKILL ends the wait sooner; nothing is lost).
  std::set<int> unknown;  // silent, and not known to run: died (or on another host)
  bool slow_alive = false;
  for (const int rank : active_) {
    const auto process = processes_.find(rank);
    const bool alive = process != processes_.end() && process->second.host == host_ &&
                       process_alive(process->second.pid);
    if (alive) {
      slow_alive = true;
    } else {
      unknown.insert(rank);
    }
  }
  if (slow_alive && Clock::now() < stop_deadline_ + kSlowWorkerWait) return;
  const std::string dead = ranks_words(unknown);
  if (!dead.empty()) {
    std::fprintf(stderr,
                 "ggk: error: %s died or was killed: it did not answer the %s that mpirun then "
                 "sent every rank\n",
                 dead.c_str(), StopSignals::name_of(stop_signal_));
    std::fflush(stderr);
  }
  release_stopped_workers();
  std::_Exit(dead.empty() ? 128 + stop_signal_ : 1);
}

void Coordinator::coordinate() {
  while (!active_.empty() || !local_finished_) {
    if (const int signal = writer_.stop_signals().received()) start_stopping(signal);
    if (stop_signal_ != 0) {
      release_waiting_workers();  // idle between looks: nothing of theirs is in flight
      if (stop_reported_ || !all_runs_done()) {
        stop_for_signal();
      } else if (Clock::now() >= stop_deadline_) {
        break;  // the workers not heard from since are gone; nothing was lost
      }
    }
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
    if (arrived) {
      receive(status);
      continue;
    }
    if (looks_) advance_look_when_idle();
    const auto now = Clock::now();
    for (const auto& [rank, held] : held_) {
      const double silent = std::chrono::duration<double>(now - held.last_heard).count();
      if (held.run >= 0 && silent > options_.rank_timeout_seconds && stop_signal_ == 0) {
        stop_now("error: rank " + std::to_string(rank) + " stopped answering (silent for " +
                     std::to_string(static_cast<int>(silent)) + " s) while holding " +
                     unit_words(study_, {held.configuration, held.run}),
                 1);
      }
    }
    if (writer_.failed()) {
      try {
        writer_.wait();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "ggk: error: %s\n", e.what());
      }
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

int Coordinator::run(RunSummary& summary) {
  const auto started = Clock::now();
  const auto fits_per_run =
      static_cast<std::int32_t>(expand_points(study_.configurations.front()).size());
  for (int rank = 1; rank < size_; ++rank) active_.insert(rank);

  std::thread local([this] { compute_locally(); });
  try {
    coordinate();
  } catch (...) {
    // An error here (a look's rule refused, a malformed message): rank 0's own
    // compute thread is told to stop and joined before the error goes on.
    fail("rank 0 stopped coordinating");
    local.join();
    throw;
  }
  local.join();
  writer_.wait();  // rethrows a write failure
  if (failed()) {
    std::fprintf(stderr, "ggk: error: %s\nggk: %s\n", failure_.c_str(),
                 writer_.target().temporary().empty() ? writer_.go_on().published.c_str()
                                                      : writer_.go_on().unpublished.c_str());
    return 1;
  }
  writer_.finish();

  summary.output = writer_.target().output();
  summary.runs_computed = total_;
  summary.runs_in_pieces = runs_in_pieces_;
  summary.runs_skipped =
      looks_ ? static_cast<std::int32_t>(looks_->runs_used() - total_) : skipped_;
  summary.fits = static_cast<std::int64_t>(total_) * fits_per_run;
  summary.failed_fits = failed_fits_.load();
  if (looks_) summary.adaptive = adaptive_summary_lines(looks_->state(), study_, options_.run);
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
  std::optional<Study> study;
  std::optional<ComputeThreads> threads;
  // Rank 0 checks the output's folder; the others only read the job.
  JobLoadOptions load = options.load;
  if (rank != 0) load.check_output = false;
  if (const int status = agree(attempt([&] {
                                 study.emplace(load_study(job_path, task_tables(), load));
                                 refuse_adaptive_shards(*study, options.run);
                                 threads.emplace(options.run.threads);
                               }),
                               rank, size)) {
    return status;
  }
  const JobSpec& job = study->job();
  if (const int status = agree(check_same_job(job, rank), rank, size)) return status;

  std::optional<OpenedResults> opened;
  if (rank == 0) {
    const Outcome outcome = attempt([&] {
      check_adaptive_metrics(*study);
      check_study_memory(*study, options.run);  // before the output is created or touched
      opened.emplace(open_results(*study, options.run, /*under_mpi=*/true));
      print_notes(opened->notes);  // as run_study does: a salvaged file, a grown one
      if (!options.run.quiet) print_notes(opened->info);
    });
    if (const int status = agree(outcome, rank, size)) return status;
  } else if (const int status = agree({}, rank, size)) {
    return status;
  }

  if (rank != 0) return work(*study);

  int status = 0;
  const Outcome outcome = attempt([&] {
    Coordinator coordinator(*study, options, size, std::move(*opened));
    RunSummary summary;
    status = coordinator.run(summary);
    if (status == 0 && !options.run.quiet) print_run_summary(job, summary);
    std::fflush(stderr);
    coordinator.release_stopped_workers();  // a stop signal that came after the last run
  });
  if (outcome.status != 0) {
    std::fprintf(stderr, "ggk: error: %s\n", outcome.message.c_str());
    MPI_Abort(MPI_COMM_WORLD, outcome.status);
  }
  return status;
}

}  // namespace ggk::engine
