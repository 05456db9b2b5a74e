#include "support/determinism_job.hpp"

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::test_support {

namespace fs = std::filesystem;

const char* const kSmallMap = R"(
#########
#...#...#
#.#.....#
#...#..G#
##.####.#
#.......#
#########
)";

std::string determinism_job(const fs::path& output) {
  return std::string(R"(name = "determinism"
task = "maze"
runs = 3
seed = 20240917
[sweep]
basis = ["ggk", "ogk"]
kernels = [4, 8]
sigma = [3.0]
solver = ["brm", "lstdq"]
[maze]
map = """)") +
         kSmallMap + R"("""
slip = 0.2
series = 6
steps_per_series = 80
test_max_steps = 40
[output]
file = ")" +
         output.string() +
         R"("
)";
}

engine::RunOptions options_for(const fs::path& output, std::int32_t threads) {
  engine::RunOptions options;
  options.output = output;
  options.threads = threads;
  options.quiet = true;
  return options;
}

void JobRunnerTest::SetUp() {
  scratch_ = std::make_unique<ScratchDir>("ggk-job-runner");
  dir_ = scratch_->path();
}

engine::JobSpec JobRunnerTest::load_job(const std::string& name, const std::string& text) const {
  return engine::load_job_file(write_file(dir_ / name, text), engine::task_tables());
}

}  // namespace ggk::test_support
