#include "engine/store/store_writer.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

class StoreWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("ggk_store_writer_test_" + std::to_string(::getpid()) +
                                        "_" + std::to_string(counter++) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path file_path() const { return dir_ / "store.h5"; }

  fs::path dir_;
};

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

std::string run_path(int run) {
  return "/maze/run_" + std::to_string(run) + "/rewards";
}

TEST_F(StoreWriterTest, ManyProducersAllLandAndOnlyTheWriterThreadTouchesTheFile) {
  constexpr int kRuns = 2000;
  std::set<std::thread::id> job_threads;  // touched by jobs only, i.e. one thread
  {
    StoreWriter writer(Hdf5File::create(file_path()), 8);
    tbb::parallel_for(0, kRuns, [&](int run) {
      const std::vector<double> rewards = {static_cast<double>(run), -1.0 * run};
      writer.submit([&job_threads, run, rewards](Hdf5File& file) {
        job_threads.insert(std::this_thread::get_id());
        file.write_vector(run_path(run), rewards);
      });
    });
    writer.wait();
    auto count = writer.submit_and_wait([](Hdf5File& file) {
      int found = 0;
      for (int run = 0; run < kRuns; ++run) found += file.exists(run_path(run)) ? 1 : 0;
      return found;
    });
    EXPECT_EQ(count.get(), kRuns);
    writer.close();
  }
  ASSERT_EQ(job_threads.size(), 1U);
  EXPECT_NE(*job_threads.begin(), std::this_thread::get_id());
  const auto file = Hdf5File::open_read_only(file_path());
  for (int run = 0; run < kRuns; ++run) {
    EXPECT_EQ(file.read_vector<double>(run_path(run)),
              (std::vector<double>{static_cast<double>(run), -1.0 * run}));
  }
}

TEST_F(StoreWriterTest, JobsFromOneProducerRunInOrder) {
  std::vector<int> order;
  {
    StoreWriter writer(Hdf5File::create(file_path()), 4);
    for (int i = 0; i < 100; ++i) writer.submit([&order, i](Hdf5File&) { order.push_back(i); });
    writer.wait();
  }
  ASSERT_EQ(order.size(), 100U);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(order[i], i);
}

TEST_F(StoreWriterTest, SubmitBlocksWhileTheQueueIsFull) {
  StoreWriter writer(Hdf5File::create(file_path()), 2);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::promise<void> started;
  writer.submit([released, &started](Hdf5File&) {
    started.set_value();
    released.wait();
  });
  started.get_future().wait();  // the writer now holds the first job; the queue is empty
  writer.submit([](Hdf5File&) {});
  writer.submit([](Hdf5File&) {});  // queue full
  std::atomic<bool> third_queued{false};
  std::thread producer([&] {
    writer.submit([](Hdf5File&) {});
    third_queued = true;
  });
  std::this_thread::sleep_for(200ms);
  EXPECT_FALSE(third_queued.load());
  release.set_value();
  producer.join();
  EXPECT_TRUE(third_queued.load());
  writer.wait();
}

TEST_F(StoreWriterTest, ExceptionInAJobSurfacesAtWaitAndLaterJobsAreSkipped) {
  StoreWriter writer(Hdf5File::create(file_path()));
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> later_job_ran{false};
  writer.submit([released](Hdf5File&) { released.wait(); });
  writer.submit([](Hdf5File&) { throw std::runtime_error("boom in run 7"); });
  writer.submit([&later_job_ran](Hdf5File&) { later_job_ran = true; });
  release.set_value();
  try {
    writer.wait();
    FAIL() << "wait() did not rethrow";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "boom in run 7");
  }
  EXPECT_FALSE(later_job_ran.load());
  EXPECT_TRUE(writer.failed());
  // The writer stays failed: the next calls rethrow as well.
  EXPECT_THROW(writer.submit([](Hdf5File&) {}), std::runtime_error);
  EXPECT_THROW(writer.wait(), std::runtime_error);
  EXPECT_THROW(writer.close(), std::runtime_error);
}

TEST_F(StoreWriterTest, Hdf5ErrorInAJobSurfacesAtTheNextSubmitNamingThePath) {
  StoreWriter writer(Hdf5File::create(file_path()));
  writer.submit([](Hdf5File& file) { file.write_vector("/maze/x", std::vector<double>{1}); });
  writer.submit([](Hdf5File& file) { file.write_vector("/maze/x", std::vector<double>{2}); });
  while (!writer.failed()) std::this_thread::sleep_for(1ms);
  try {
    writer.submit([](Hdf5File&) {});
    FAIL() << "submit() did not rethrow";
  } catch (const std::runtime_error& error) {
    EXPECT_TRUE(contains(error.what(), "'/maze/x': already exists"));
  }
}

TEST_F(StoreWriterTest, SubmitAndWaitReturnsResultsAndKeepsReadErrorsToItself) {
  StoreWriter writer(Hdf5File::create(file_path()));
  writer.submit([](Hdf5File& file) { file.write_vector("v", std::vector<std::int64_t>{4, 5}); });
  auto values =
      writer.submit_and_wait([](Hdf5File& file) { return file.read_vector<std::int64_t>("v"); });
  ASSERT_EQ(values.wait_for(0s), std::future_status::ready);
  EXPECT_EQ(values.get(), (std::vector<std::int64_t>{4, 5}));

  auto missing = writer.submit_and_wait([](Hdf5File& file) { return file.read_strings("nope"); });
  ASSERT_EQ(missing.wait_for(0s), std::future_status::ready);
  try {
    missing.get();
    FAIL() << "reading a missing dataset did not throw";
  } catch (const std::runtime_error& error) {
    EXPECT_TRUE(contains(error.what(), "'/nope'"));
  }
  EXPECT_FALSE(writer.failed());
  auto done = writer.submit_and_wait([](Hdf5File& file) { file.flush(); });
  EXPECT_NO_THROW(done.get());
  EXPECT_NO_THROW(writer.wait());
}

TEST_F(StoreWriterTest, ReadAfterAFailureReportsTheFailure) {
  StoreWriter writer(Hdf5File::create(file_path()));
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  writer.submit([released](Hdf5File&) {
    released.wait();
    throw std::runtime_error("disk full");
  });
  std::thread releaser([&] {
    std::this_thread::sleep_for(50ms);
    release.set_value();
  });
  // Queued before the failure (the usual case), run after it: the future
  // carries the failure. Queued after it, submit_and_wait itself rethrows.
  try {
    auto read = writer.submit_and_wait([](Hdf5File&) { return 1; });
    read.get();
    ADD_FAILURE() << "the read ran after the writer failed";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "disk full");
  }
  releaser.join();
  EXPECT_THROW(writer.wait(), std::runtime_error);
}

TEST_F(StoreWriterTest, SubmittingFromAJobIsALogicError) {
  StoreWriter writer(Hdf5File::create(file_path()));
  writer.submit([&writer](Hdf5File&) { writer.submit([](Hdf5File&) {}); });
  EXPECT_THROW(writer.wait(), std::logic_error);
}

TEST_F(StoreWriterTest, DestructorDrainsTheQueue) {
  {
    StoreWriter writer(Hdf5File::create(file_path()), 4);
    for (int run = 0; run < 50; ++run) {
      writer.submit([run](Hdf5File& file) {
        file.write_vector(run_path(run), std::vector<double>{1.0 * run});
      });
    }
  }
  const auto file = Hdf5File::open_read_only(file_path());
  for (int run = 0; run < 50; ++run) {
    EXPECT_EQ(file.read_vector<double>(run_path(run)), std::vector<double>{1.0 * run});
  }
}

TEST_F(StoreWriterTest, DestructorPrintsAFailureNobodySaw) {
  ::testing::internal::CaptureStderr();
  {
    StoreWriter writer(Hdf5File::create(file_path()));
    writer.submit([](Hdf5File&) { throw std::runtime_error("lost write"); });
  }
  const std::string printed = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(contains(printed, "lost write"));
}

TEST_F(StoreWriterTest, CloseClosesTheFileAndRefusesMoreJobs) {
  StoreWriter writer(Hdf5File::create(file_path()));
  writer.submit([](Hdf5File& file) { file.write_int64_attribute("/", "complete", 1); });
  writer.close();
  EXPECT_THROW(writer.submit([](Hdf5File&) {}), std::logic_error);
  // The file is closed, so it can be opened again.
  EXPECT_EQ(Hdf5File::open_read_only(file_path()).read_int64_attribute("/", "complete"), 1);
}

// A writer whose queue never runs empty (runs finish faster than they are
// written) still closes the file for a moment about once a second: another
// process (h5ls) gets in long before the last job. Before the reader window,
// the file stayed open, and locked, until the queue ran dry.
TEST_F(StoreWriterTest, AReaderGetsInWhileTheQueueNeverRunsEmpty) {
  if (std::system("command -v h5ls >/dev/null 2>&1") != 0) GTEST_SKIP() << "no h5ls";
  constexpr int kJobs = 40;  // 100 ms each: 4 s of writing, queued at once
  std::atomic<int> done{0};
  StoreWriter writer(Hdf5File::create(file_path()), kJobs + 1,
                     StoreWriter::WhenIdle::kCloseForReaders);
  for (int run = 0; run < kJobs; ++run) {
    writer.submit([&done, run](Hdf5File& file) {
      std::this_thread::sleep_for(100ms);
      file.write_vector(run_path(run), std::vector<double>{1.0 * run});
      ++done;
    });
  }
  const std::string h5ls = "h5ls " + file_path().string() + " >/dev/null 2>&1";
  int done_when_read = -1;
  while (done.load() < kJobs) {
    if (std::system(h5ls.c_str()) == 0) {
      done_when_read = done.load();
      break;
    }
    std::this_thread::sleep_for(50ms);
  }
  writer.close();
  EXPECT_GE(done_when_read, 0) << "h5ls never opened the file while the writer had work";
  EXPECT_LT(done_when_read, kJobs - 5) << "h5ls got in only at the end";
}

}  // namespace
}  // namespace ggk::engine
