#include "engine/store/store_writer.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace ggk::engine {

StoreWriter::StoreWriter(Hdf5File file, std::size_t queue_capacity, WhenIdle when_idle)
    : file_(std::move(file)),
      capacity_(queue_capacity),
      when_idle_(when_idle),
      opened_at_(std::chrono::steady_clock::now()) {
  if (capacity_ == 0) throw std::invalid_argument("StoreWriter queue capacity must be >= 1");
  thread_ = std::thread([this] { run_jobs(); });
}

StoreWriter::~StoreWriter() {
  stop_thread();
  if (file_ && failure_ && !parked_) file_->abandon();  // see close()
  file_.reset();
  if (failure_ && !failure_reported_) {
    // The last place the error can still be seen; losing it silently would hide
    // a missing or partial result.
    try {
      std::rethrow_exception(failure_);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "ggk: store writer: a write failed and nobody was told: %s\n",
                   error.what());
    } catch (...) {
      std::fprintf(stderr, "ggk: store writer: a write failed with a non-standard exception\n");
    }
  }
}

void StoreWriter::require_not_writer_thread(const char* what) const {
  if (std::this_thread::get_id() == thread_.get_id()) {
    throw std::logic_error(std::string("StoreWriter::") + what +
                           " called from a job on the writer thread (it would wait on itself)");
  }
}

void StoreWriter::rethrow_failure(std::unique_lock<std::mutex>& lock) {
  failure_reported_ = true;
  const std::exception_ptr failure = failure_;
  lock.unlock();
  std::rethrow_exception(failure);
}

void StoreWriter::submit(Job job) {
  if (!job) throw std::invalid_argument("StoreWriter::submit: empty job");
  enqueue(Entry{std::move(job), nullptr});
}

void StoreWriter::enqueue(Entry entry) {
  require_not_writer_thread("submit");
  std::unique_lock lock(mutex_);
  space_available_.wait(lock, [this] { return queue_.size() < capacity_ || failure_ || closed_; });
  if (failure_) rethrow_failure(lock);
  if (closed_) throw std::logic_error("StoreWriter::submit after close()");
  queue_.push_back(std::move(entry));
  ++pending_;
  work_available_.notify_one();
}

void StoreWriter::wait() {
  require_not_writer_thread("wait");
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return pending_ == 0; });
  if (failure_) rethrow_failure(lock);
}

void StoreWriter::close() {
  require_not_writer_thread("close");
  stop_thread();
  // Closing writes what HDF5 still buffers: a failure there (a full disk) is
  // an error of the job, not something to drop.
  // After a failed write the file is abandoned, not closed (Hdf5File::abandon):
  // it stays as the last successful flush left it.
  std::exception_ptr close_failure;
  if (parked_) {
    // Closed already, after its last commit.
  } else if (file_ && !failed()) {
    try {
      file_->close();
    } catch (...) {
      close_failure = std::current_exception();
    }
  } else if (file_) {
    file_->abandon();
  }
  file_.reset();
  std::unique_lock lock(mutex_);
  if (failure_) rethrow_failure(lock);
  if (close_failure) std::rethrow_exception(close_failure);
}

bool StoreWriter::failed() const {
  std::lock_guard lock(mutex_);
  return static_cast<bool>(failure_);
}

void StoreWriter::stop_thread() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    closed_ = true;
  }
  work_available_.notify_all();
  space_available_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void StoreWriter::park_file() {
  parked_path_ = file_->path();
  parked_gzip_level_ = file_->gzip_level();
  file_->close();  // every commit flushed already: this writes little
  parked_ = true;
}

void StoreWriter::unpark_file() {
  *file_ = Hdf5File::reopen_for_writer(parked_path_);
  file_->set_gzip_level(parked_gzip_level_);
  parked_ = false;
  opened_at_ = std::chrono::steady_clock::now();
}

void StoreWriter::run_jobs() {
  std::unique_lock lock(mutex_);
  for (;;) {
    work_available_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, and every job has run
    Entry entry = std::move(queue_.front());
    queue_.pop_front();
    const std::exception_ptr earlier_failure = failure_;
    lock.unlock();
    space_available_.notify_one();

    std::exception_ptr failure;
    if (earlier_failure) {
      if (entry.cancel) entry.cancel(earlier_failure);
    } else {
      try {
        if (parked_) unpark_file();
        entry.run(*file_);
      } catch (...) {
        failure = std::current_exception();
      }
    }
    entry = Entry{};  // free the job's captured data outside the lock

    lock.lock();
    const bool idle = queue_.empty();
    const bool overdue = std::chrono::steady_clock::now() - opened_at_ >= kReaderWindowEvery;
    if (!failure && !failure_ && (idle || overdue) && when_idle_ == WhenIdle::kCloseForReaders &&
        !parked_ && file_ && !file_->in_memory()) {
      lock.unlock();
      try {
        park_file();
        // Work is waiting: stay closed long enough for a retrying reader to
        // get in (it then holds HDF5's lock; unpark_file waits for it).
        if (!idle) std::this_thread::sleep_for(kReaderWindow);
      } catch (...) {
        failure = std::current_exception();
      }
      lock.lock();
    }
    if (failure && !failure_) {
      failure_ = failure;
      space_available_.notify_all();  // blocked producers must see the failure
    }
    if (--pending_ == 0) idle_.notify_all();
  }
}

}  // namespace ggk::engine
