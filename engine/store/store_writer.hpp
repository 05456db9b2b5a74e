#pragma once
// StoreWriter: the one thread that makes every HDF5 call of a run of the engine.
//
// HDF5 cannot be entered from several threads at once (builds without its
// thread-safe option), or serialises every call on one lock (builds with it),
// so producers (oneTBB tasks) never touch the file: they submit jobs, closures that receive the
// Hdf5File, and the writer thread runs them one at a time in submission order (FIFO; jobs from one
// producer keep their order). The queue is bounded: submit() blocks while
// `queue_capacity` jobs wait, so fast producers cannot pile up unbounded result
// data in memory.
//
// Failure: the first exception thrown by a job is kept; from then on the writer
// has failed: queued and later jobs are skipped (never run half a run after a
// failed write, in particular never the job that marks a run complete), and every
// later submit(), wait() and close() rethrows that exception. The engine then
// stops; --resume redoes the incomplete runs. A failed writer abandons its file
// instead of closing it (Hdf5File::abandon: closing would write cached metadata
// about data that never reached the disk). Nothing is swallowed: an error
// no caller saw by the time of destruction is printed to stderr by the destructor.
//
// Readers while it writes: with WhenIdle::kCloseForReaders the writer closes
// the file whenever its queue runs empty (after a run is committed) and opens it
// again for the next job (Hdf5File::reopen_for_writer), so that h5py, h5ls and
// `ggk info` can open the file between two commits instead of failing on HDF5's
// lock until the job ends. When the queue never runs empty (runs finish faster
// than they are written, e.g. on a loaded machine) the writer still closes the
// file once it has been open for kReaderWindowEvery, and leaves it closed for
// kReaderWindow, longer than a reader's retry interval (50 ms,
// Hdf5File::open_waiting_for_lock): a reader is never shut out for the whole
// job. In-memory files are never closed.
//
// Thread-safety: submit(), submit_and_wait(), wait() and failed() may be called
// concurrently from any threads except the writer thread itself (a job calling
// them would wait on itself; that throws std::logic_error). close() and the
// destructor must not run concurrently with other calls.

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>

#include "engine/hdf5/hdf5_file.hpp"

namespace ggk::engine {

class StoreWriter {
 public:
  using Job = std::function<void(Hdf5File&)>;
  static constexpr std::size_t kDefaultQueueCapacity = 64;
  enum class WhenIdle { kKeepOpen, kCloseForReaders };
  static constexpr std::chrono::milliseconds kReaderWindowEvery{1000};
  static constexpr std::chrono::milliseconds kReaderWindow{120};

  // Takes the file over and starts the writer thread.
  explicit StoreWriter(Hdf5File file, std::size_t queue_capacity = kDefaultQueueCapacity,
                       WhenIdle when_idle = WhenIdle::kKeepOpen);
  // Runs the queued jobs, stops the thread and closes the file. Never throws.
  ~StoreWriter();

  StoreWriter(const StoreWriter&) = delete;
  StoreWriter& operator=(const StoreWriter&) = delete;
  StoreWriter(StoreWriter&&) = delete;
  StoreWriter& operator=(StoreWriter&&) = delete;

  // Queues a write; blocks while the queue is full. Rethrows the writer's
  // failure, if any (the job is then not queued).
  void submit(Job job);

  // Queues `read` (a copyable callable taking Hdf5File&), blocks until it ran
  // and returns a ready future holding its result or the exception it threw.
  // A read's exception does not make the writer fail. If the writer failed
  // before the read ran, the future holds the writer's failure.
  template <class Read>
  auto submit_and_wait(Read read) -> std::future<std::invoke_result_t<Read&, Hdf5File&>>;

  // Blocks until every queued job ran; rethrows the writer's failure, if any.
  void wait();

  // wait(), then stops the thread and closes the file. Rethrows the failure,
  // if any, or the failure to close the file; later submit() calls throw
  // std::logic_error.
  void close();

  bool failed() const;

 private:
  struct Entry {
    Job run;
    // Called instead of run when the writer failed before the job's turn.
    std::function<void(std::exception_ptr)> cancel;
  };

  void enqueue(Entry entry);
  void run_jobs();
  void stop_thread();
  void require_not_writer_thread(const char* what) const;
  [[noreturn]] void rethrow_failure(std::unique_lock<std::mutex>& lock);

  // Writer thread only: closes the file for readers / opens it again.
  void park_file();
  void unpark_file();

  std::optional<Hdf5File> file_;
  const std::size_t capacity_;
  const WhenIdle when_idle_;
  // While parked (closed for readers): where the file is and how it writes.
  std::filesystem::path parked_path_;
  int parked_gzip_level_ = 4;
  bool parked_ = false;
  std::chrono::steady_clock::time_point opened_at_;  // when the file was last (re)opened

  mutable std::mutex mutex_;
  std::condition_variable work_available_;   // writer waits: queue non-empty or stopping
  std::condition_variable space_available_;  // producers wait: queue below capacity
  std::condition_variable idle_;             // wait(): no job queued or running
  std::deque<Entry> queue_;
  std::size_t pending_ = 0;  // queued + running
  bool stopping_ = false;
  bool closed_ = false;
  std::exception_ptr failure_;
  bool failure_reported_ = false;

  std::thread thread_;  // last: starts after every other member is ready
};

template <class Read>
auto StoreWriter::submit_and_wait(Read read)
    -> std::future<std::invoke_result_t<Read&, Hdf5File&>> {
  using Result = std::invoke_result_t<Read&, Hdf5File&>;
  auto promise = std::make_shared<std::promise<Result>>();
  std::future<Result> future = promise->get_future();
  Entry entry;
  entry.run = [promise, read = std::move(read)](Hdf5File& file) mutable {
    try {
      if constexpr (std::is_void_v<Result>) {
        read(file);
        promise->set_value();
      } else {
        promise->set_value(read(file));
      }
    } catch (...) {
      promise->set_exception(std::current_exception());
    }
  };
  entry.cancel = [promise](std::exception_ptr failure) { promise->set_exception(failure); };
  enqueue(std::move(entry));
  future.wait();
  return future;
}

}  // namespace ggk::engine
