// The [arm] table of job files, and the calibrated geometry of the shipped
// jobs/arm-paper.toml: the three properties it was tuned for (sims/arm/README.md).

#include "engine/tasks/arm/arm_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/tasks/seeds.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/arm/arm.hpp"
#include "support/job_text.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;
using sims::arm::Arm;
using sims::arm::ArmConfig;

// A valid arm job; line numbers below refer to it.
constexpr const char* kArmJob = R"(name = "arm-test"
task = "arm"
runs = 2
seed = 1
[sweep]
kernels = [16]
sigma = [1.0]
[arm]
links = [1.0, 1]
start_A = [110, 0]
[arm.object]
center = [1.25, 0.2]
radius = 0.2
[[arm.obstacles]]
kind = "rectangle"
min = [-3.0, -2.0]
max = [3.0, -0.1]
[[arm.obstacles]]
kind = "disc"
center = [0.0, 1.6]
radius = 0.3
)";

// kArmJob with line `line` (1-based) replaced by `text` (which may hold several lines).
std::string arm_job_with(int line, const std::string& text) {
  return with_line(kArmJob, line, text);
}

// `job` cut before its first [[arm.obstacles]].
std::string without_obstacles(const std::string& job) {
  return job.substr(0, job.find("[[arm.obstacles]]"));
}

std::string arm_job_error(const std::string& text) {
  try {
    parse_job(text, "bad.toml", task_tables(), no_output_check());
  } catch (const JobError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a JobError for:\n" << text;
  return {};
}

TEST(ArmTable, ReadsKeysAndDefaults) {
  const JobSpec job = parse_job(kArmJob, "arm.toml", task_tables(), no_output_check());
  EXPECT_EQ(job.task, "arm");
  ASSERT_TRUE(job.task_config.type() == typeid(ArmConfig));
  const ArmConfig& config = task_config_as<ArmConfig>(job);
  EXPECT_EQ(config.geometry.link1_length, 1.0);
  EXPECT_EQ(config.geometry.link2_length, 1.0);
  EXPECT_EQ(config.geometry.base, (sims::arm::Point2{0.0, 0.0}));
  EXPECT_EQ(config.limits.shoulder_min_deg, 0);
  EXPECT_EQ(config.limits.shoulder_max_deg, 180);
  EXPECT_EQ(config.limits.elbow_min_deg, -180);
  EXPECT_EQ(config.limits.elbow_max_deg, 175);
  EXPECT_EQ(config.start_A, (sims::arm::JointAngles{110, 0}));
  EXPECT_EQ(config.geometry.object, (sims::arm::Disc{{1.25, 0.2}, 0.2}));
  ASSERT_EQ(config.geometry.obstacles.size(), 2u);
  EXPECT_EQ(std::get<sims::arm::Rectangle>(config.geometry.obstacles[0]),
            (sims::arm::Rectangle{{-3.0, -2.0}, {3.0, -0.1}}));
  EXPECT_EQ(std::get<sims::arm::Disc>(config.geometry.obstacles[1]),
            (sims::arm::Disc{{0.0, 1.6}, 0.3}));
  EXPECT_EQ(config.series, 50);
  EXPECT_EQ(config.steps_per_series, 1000);
  EXPECT_EQ(config.test_max_steps, 100);
  EXPECT_EQ(config.grid_step_tenths, 50);  // the paper's 5 degrees

  const JobSpec other = parse_job(arm_job_with(10, R"(start_A = [20, -5]
base = [0.25, 0.05]
shoulder_limits = [10, 170]
elbow_limits = [-150, 150]
series = 7
steps_per_series = 30
test_max_steps = 12)"),
                                  "arm.toml", task_tables(), no_output_check());
  const ArmConfig& c = task_config_as<ArmConfig>(other);
  EXPECT_EQ(c.start_A, (sims::arm::JointAngles{20, -5}));
  EXPECT_EQ(c.geometry.base, (sims::arm::Point2{0.25, 0.05}));
  EXPECT_EQ(c.limits.shoulder_min_deg, 10);
  EXPECT_EQ(c.limits.shoulder_max_deg, 170);
  EXPECT_EQ(c.limits.elbow_min_deg, -150);
  EXPECT_EQ(c.limits.elbow_max_deg, 150);
  EXPECT_EQ(c.series, 7);
  EXPECT_EQ(c.steps_per_series, 30);
  EXPECT_EQ(c.test_max_steps, 12);
}

TEST(ArmTable, ReadsTheGridStep) {
  const auto step_of = [](const std::string& value) {
    const JobSpec job =
        parse_job(arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = " + value), "arm.toml",
                  task_tables(), no_output_check());
    return task_config_as<ArmConfig>(job).grid_step_tenths;
  };
  EXPECT_EQ(step_of("5"), 50);
  EXPECT_EQ(step_of("5.0"), 50);
  EXPECT_EQ(step_of("2.5"), 25);
  EXPECT_EQ(step_of("1"), 10);
  EXPECT_EQ(step_of("0.5"), 5);
  // start_A off the 5-degree grid is on the 1-degree one.
  const JobSpec fine = parse_job(
      arm_job_with(10, "start_A = [112, -3]\ngrid_step_degrees = 1.0\nshoulder_limits = [1, 179]"),
      "arm.toml", task_tables(), no_output_check());
  const ArmConfig& config = task_config_as<ArmConfig>(fine);
  EXPECT_EQ(config.start_A, (sims::arm::JointAngles{112, -3}));
  EXPECT_EQ(config.limits.shoulder_min_deg, 1);
  const Arm arm(config);
  EXPECT_EQ(arm.shoulder_steps(), 179);
  EXPECT_EQ(arm.elbow_steps(), 356);
  EXPECT_EQ(arm.angles_of(arm.start_state_A()), (sims::arm::JointAngles{112.0, -3.0}));
}

struct MalformedArm {
  std::string what;
  std::string text;
  std::vector<std::string> expected;  // substrings of the message
};

std::vector<MalformedArm> malformed_arms() {
  const std::string job = kArmJob;
  const std::string no_arm = job.substr(0, job.find("[arm]"));
  std::string without_object = job;
  const std::string object = "[arm.object]\ncenter = [1.25, 0.2]\nradius = 0.2\n";
  without_object.erase(without_object.find(object), object.size());
  return {
      {"[arm] missing", no_arm, {"bad.toml: arm: required table [arm] is missing"}},
      {"[arm] with task maze",
       arm_job_with(2, "task = \"maze\"") + "[maze]\nmap = \"G.\"\n",
       {"bad.toml:8:2: arm: table [arm] belongs to task 'arm', but task = \"maze\""}},
      {"[maze] with task arm",
       job + "[maze]\nslip = 0.1\n",
       {"bad.toml:22:2: maze: table [maze] belongs to task 'maze', but task = \"arm\""}},
      {"unknown key with suggestion",
       arm_job_with(10, "start_a = [110, 0]"),
       {"bad.toml:10:1: [arm] start_a: unknown key; did you mean 'start_A'?"}},
      {"singular obstacle table",
       arm_job_with(14, "[[arm.obstacle]]"),
       {"bad.toml:", "[arm] obstacle: unknown key; did you mean 'obstacles'?"}},
      {"links missing", arm_job_with(9, ""), {"bad.toml:", "[arm] links: required key"}},
      {"links a number",
       arm_job_with(9, "links = 1.0"),
       {"bad.toml:9:1: [arm] links: expected an array of 2 numbers", "got 1.0"}},
      {"three links",
       arm_job_with(9, "links = [1, 1, 1]"),
       {"bad.toml:9:1: [arm] links:", "got an array of 3 elements"}},
      {"negative link",
       arm_job_with(9, "links = [1.0, -0.5]"),
       {"bad.toml:9:15: [arm] links: expected a length > 0.0 for link2, got -0.5"}},
      {"base with a string",
       arm_job_with(9, "links = [1, 1]\nbase = [0, \"0\"]"),
       {"bad.toml:10:12: [arm] base: expected a finite number for y, got \"0\""}},
      {"base not finite",
       arm_job_with(9, "links = [1, 1]\nbase = [nan, 0]"),
       {"bad.toml:10:9: [arm] base:", "got nan"}},
      {"limits off the 5-degree grid",
       arm_job_with(9, "links = [1, 1]\nshoulder_limits = [0, 178]"),
       {"bad.toml:10:23: [arm] shoulder_limits:", "multiples of 5", "got 178"}},
      {"limits as floats",
       arm_job_with(9, "links = [1, 1]\nelbow_limits = [-180.0, 175]"),
       {"bad.toml:10:17: [arm] elbow_limits: expected integer degrees", "got -180.0"}},
      {"limits reversed",
       arm_job_with(9, "links = [1, 1]\nelbow_limits = [175, -180]"),
       {"bad.toml:10:1: [arm] elbow_limits: expected min <= max, got [175, -180]"}},
      {"limits spanning a full turn",
       arm_job_with(9, "links = [1, 1]\nelbow_limits = [-180, 180]"),
       {"bad.toml:10:1: [arm] elbow_limits:", "span 360 degrees"}},
      {"start_A missing", arm_job_with(10, ""), {"bad.toml:", "[arm] start_A: required key"}},
      {"start_A colliding",
       arm_job_with(10, "start_A = [90, 0]"),
       {"bad.toml:10:1: [arm] start_A:", "(90, 0) collides with an obstacle"}},
      {"start_A on the goal",
       arm_job_with(10, "start_A = [60, -100]"),
       {"bad.toml:10:1: [arm] start_A:", "is already a goal"}},
      {"start_A outside the limits",
       arm_job_with(10, "start_A = [-5, 0]"),
       {"bad.toml:10:1: [arm] start_A:", "outside the joint limits"}},
      {"start_A off the grid",
       arm_job_with(10, "start_A = [112, 0]"),
       {"bad.toml:10:12: [arm] start_A:", "multiples of 5", "got 112"}},
      {"object missing",
       without_object,
       {"bad.toml:8:1: [arm] object: required table [arm.object] is missing"}},
      {"object unknown key",
       arm_job_with(12, "centre = [1.25, 0.2]"),
       {"bad.toml:12:1: [arm.object] centre: unknown key; did you mean 'center'?"}},
      {"object radius 0",
       arm_job_with(13, "radius = 0"),
       {"bad.toml:13:1: [arm.object] radius: expected a number > 0.0, got 0"}},
      {"object out of reach",
       arm_job_with(12, "center = [5.0, 0.2]"),
       {"bad.toml:11:1: [arm] object:", "no collision-free pose", "on the object"}},
      {"obstacle kind unknown",
       arm_job_with(15, "kind = \"rectangel\""),
       {"bad.toml:15:1: [arm.obstacles[0]] kind:", "got \"rectangel\"; did you mean 'rectangle'?"}},
      {"obstacle kind missing",
       arm_job_with(15, ""),
       {"bad.toml:", "[arm.obstacles[0]] kind: required key"}},
      {"rectangle with a radius",
       arm_job_with(15, "kind = \"rectangle\"\nradius = 1"),
       {"bad.toml:16:1: [arm.obstacles[0]] radius: a rectangle has no key 'radius'"}},
      {"disc with min",
       arm_job_with(19, "kind = \"disc\"\nmin = [0, 0]"),
       {"bad.toml:20:1: [arm.obstacles[1]] min: a disc has no key 'min'"}},
      {"unknown obstacle key",
       arm_job_with(21, "radius = 0.3\nradios = 1"),
       {"bad.toml:22:1: [arm.obstacles[1]] radios: unknown key; did you mean 'radius'?"}},
      {"rectangle min > max",
       arm_job_with(17, "max = [3.0, -2.5]"),
       {"bad.toml:17:1: [arm.obstacles[0]] max: expected max >= min"}},
      {"disc radius negative",
       arm_job_with(21, "radius = -0.3"),
       {"bad.toml:21:1: [arm.obstacles[1]] radius: expected a number > 0.0, got -0.3"}},
      {"obstacles not tables",
       without_obstacles(
           arm_job_with(10, "start_A = [110, 0]\nobstacles = [{kind = \"disc\"}, 2]")),
       {"bad.toml:11:31: [arm] obstacles: expected a table", "got 2"}},
      {"obstacles not an array",
       without_obstacles(arm_job_with(10, "start_A = [110, 0]\nobstacles = 1")),
       {"bad.toml:11:1: [arm] obstacles: expected an array of tables ([[arm.obstacles]]), got 1"}},
      {"every pose collides",
       job + "[[arm.obstacles]]\nkind = \"disc\"\ncenter = [0, 0]\nradius = 0.5\n",
       {"bad.toml:", "[arm] obstacles:", "every pose on the joint grid collides"}},
      {"series = 0",
       arm_job_with(10, "start_A = [110, 0]\nseries = 0"),
       {"bad.toml:11:1: [arm] series: expected an integer >= 1, got 0"}},
      {"too many samples",
       arm_job_with(10, "start_A = [110, 0]\nseries = 100000\nsteps_per_series = 100000"),
       {"bad.toml:12:1: [arm] steps_per_series:", "10000000000 samples"}},
      {"grid step 0",
       arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = 0"),
       {"bad.toml:11:1: [arm] grid_step_degrees:", "got 0"}},
      {"grid step negative",
       arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = -5"),
       {"bad.toml:11:1: [arm] grid_step_degrees:", "got -5"}},
      {"grid step a string",
       arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = \"5\""),
       {"bad.toml:11:1: [arm] grid_step_degrees:", "got \"5\""}},
      {"grid step of a full turn",
       arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = 360"),
       {"bad.toml:11:1: [arm] grid_step_degrees:", "got 360"}},
      {"grid step below a tenth",
       arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = 0.05"),
       {"bad.toml:11:1: [arm] grid_step_degrees:", "got 0.05"}},
      {"grid step not whole tenths",
       arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = 0.25"),
       {"bad.toml:11:1: [arm] grid_step_degrees: expected a whole number of tenths", "got 0.25"}},
      {"grid step not dividing the default elbow limits",
       arm_job_with(10, "start_A = [110, 0]\ngrid_step_degrees = 10"),
       {"bad.toml:11:1: [arm] grid_step_degrees: a grid step of 10 degrees does not divide "
        "elbow_limits [-180, 175]"}},
      {"grid step not dividing start_A",
       arm_job_with(10, "start_A = [110, 5]\ngrid_step_degrees = 10\nelbow_limits = [-180, 170]"),
       {"bad.toml:11:1: [arm] grid_step_degrees:", "does not divide start_A [110, 5]"}},
      {"start_A off a 2.5-degree grid",
       arm_job_with(10, "start_A = [112, 0]\ngrid_step_degrees = 2.5"),
       {"bad.toml:10:12: [arm] start_A:", "multiples of 2.5", "got 112"}},
      {"test_max_steps wrong type",
       arm_job_with(10, "start_A = [110, 0]\ntest_max_steps = 1.5"),
       {"bad.toml:11:1: [arm] test_max_steps:", "got 1.5"}},
      {"test_max_steps that never end",
       arm_job_with(10, "start_A = [110, 0]\ntest_max_steps = 2147483647"),
       {"bad.toml:11:1: [arm] test_max_steps: expected an integer in [1, 1000000], got "
        "2147483647"}},
  };
}

TEST(ArmTable, RejectsMalformedTables) {
  for (const MalformedArm& job : malformed_arms()) {
    const std::string message = arm_job_error(job.text);
    for (const std::string& part : job.expected) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "case '" << job.what << "': the message\n  " << message << "\nlacks\n  " << part;
    }
  }
}

// The shipped arm job files (output directories aside).
class ShippedArmJob : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* source_dir = std::getenv("GGK_SOURCE_DIR");
    if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
    jobs_ = fs::path(source_dir) / "jobs";
  }
  JobSpec load(const std::string& name) const {
    return load_job_file(jobs_ / (name + ".toml"), task_tables(), no_output_check());
  }
  fs::path jobs_;
};

// The states visited by one run's samples, drawn exactly as the discrete protocol
// draws them (engine/discrete_protocol.cpp): each series from a uniformly random
// non-goal state, uniformly random actions, a new random start after a terminal
// transition, from the run's samples stream.
std::int32_t visited_states(const Arm& arm, const ArmConfig& config, std::uint64_t seed,
                            std::int32_t run) {
  std::vector<std::int32_t> starts;
  for (std::int32_t s = 0; s < arm.num_states(); ++s) {
    if (!arm.is_goal(s)) starts.push_back(s);
  }
  kernels::RandomStream random = stream_for(seed, run, Purpose::samples);
  const auto random_start = [&] {
    return starts[static_cast<std::size_t>(
        random.uniform_index(static_cast<std::int64_t>(starts.size())))];
  };
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(arm.num_states()), 0);
  for (std::int32_t series = 0; series < config.series; ++series) {
    std::int32_t state = random_start();
    for (std::int32_t step = 0; step < config.steps_per_series; ++step) {
      const auto action = static_cast<std::int32_t>(random.uniform_index(arm.num_actions()));
      const sims::arm::StepResult r = arm.step(state, action);
      visited[static_cast<std::size_t>(state)] = 1;
      visited[static_cast<std::size_t>(r.next_state)] = 1;
      state = r.terminal ? random_start() : r.next_state;
    }
  }
  return static_cast<std::int32_t>(std::count(visited.begin(), visited.end(), std::uint8_t{1}));
}

double distance(const std::array<double, 2>& a, const std::array<double, 2>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

// The goal nearest to `state` in joint space (Euclidean distance of state vectors).
std::int32_t nearest_goal(const Arm& arm, std::int32_t state) {
  std::int32_t best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const std::int32_t goal : arm.goal_states()) {
    const double d = distance(arm.state_vector(state), arm.state_vector(goal));
    if (d < best_distance) {
      best_distance = d;
      best = goal;
    }
  }
  return best;
}

TEST_F(ShippedArmJob, PaperGeometryHasTheCalibratedProperties) {
  const JobSpec job = load("arm-paper");
  EXPECT_EQ(job.task, "arm");
  const ArmConfig& config = task_config_as<ArmConfig>(job);
  const Arm arm(config);
  EXPECT_EQ(arm.shoulder_steps(), 37);
  EXPECT_EQ(arm.elbow_steps(), 72);
  EXPECT_EQ(arm.num_states(), 1621);

  // 1. 50,000 random moves visit 1605 states within 2 % (paper: "the graph
  // induced by the above MDP consists of 1605 nodes"), for several runs.
  EXPECT_EQ(config.series * config.steps_per_series, 50000);
  for (std::int32_t run = 0; run < 5; ++run) {
    const std::int32_t nodes = visited_states(arm, config, job.seed, run);
    EXPECT_NEAR(nodes, 1605, 0.02 * 1605) << "run " << run;
  }

  // 2. Exactly 16 goal states.
  EXPECT_EQ(arm.goal_states().size(), 16u);

  // 3. A is behind the obstacle: the straight joint-space line to the nearest
  // goal crosses colliding poses, ...
  const std::int32_t a = arm.start_state_A();
  EXPECT_EQ(arm.angles_of(a), (sims::arm::JointAngles{110, 0}));
  const std::int32_t goal = nearest_goal(arm, a);
  const std::array<double, 2> from = arm.state_vector(a);
  const std::array<double, 2> to = arm.state_vector(goal);
  std::int32_t blocked_points = 0;
  constexpr int kPoints = 1000;
  for (int k = 0; k <= kPoints; ++k) {
    const double t = static_cast<double>(k) / kPoints;
    // Grid indices of the cell nearest the point (state vector = angle / 5).
    const auto i = static_cast<std::int32_t>(
        std::lround(from[0] + t * (to[0] - from[0]) - config.limits.shoulder_min_deg / 5.0));
    const auto j = static_cast<std::int32_t>(
        std::lround(from[1] + t * (to[1] - from[1]) - config.limits.elbow_min_deg / 5.0));
    if (arm.collides(i, j)) ++blocked_points;
  }
  EXPECT_GT(blocked_points, 0) << "the straight line from A to its nearest goal is free";

  // ... following the Euclidean distance to the goals downhill gets stuck at the
  // obstacle (what the paper's OGK policy does), ...
  const auto goal_distance = [&](std::int32_t s) {
    return distance(arm.state_vector(s), arm.state_vector(nearest_goal(arm, s)));
  };
  std::int32_t state = a;
  for (;;) {
    std::int32_t next = state;
    for (std::int32_t action = 0; action < arm.num_actions(); ++action) {
      const std::int32_t candidate = arm.move(state, action);
      if (goal_distance(candidate) < goal_distance(next)) next = candidate;
    }
    if (next == state) break;
    state = next;
  }
  EXPECT_FALSE(arm.is_goal(state)) << "Euclidean descent from A reaches a goal";

  // ... while a way round exists within the test's step limit (breadth-first
  // search over moves).
  std::vector<std::int32_t> steps(static_cast<std::size_t>(arm.num_states()), -1);
  std::deque<std::int32_t> queue = {a};
  steps[static_cast<std::size_t>(a)] = 0;
  std::int32_t steps_to_goal = -1;
  while (!queue.empty() && steps_to_goal < 0) {
    const std::int32_t s = queue.front();
    queue.pop_front();
    if (arm.is_goal(s)) steps_to_goal = steps[static_cast<std::size_t>(s)];
    for (std::int32_t action = 0; action < arm.num_actions(); ++action) {
      const std::int32_t t = arm.move(s, action);
      if (steps[static_cast<std::size_t>(t)] >= 0) continue;
      steps[static_cast<std::size_t>(t)] = steps[static_cast<std::size_t>(s)] + 1;
      queue.push_back(t);
    }
  }
  EXPECT_EQ(steps_to_goal, 43);
  EXPECT_LE(steps_to_goal, config.test_max_steps);
}

TEST_F(ShippedArmJob, QuickJobUsesThePaperGeometry) {
  const JobSpec paper = load("arm-paper");
  const JobSpec quick = load("arm-quick");
  const ArmConfig& a = task_config_as<ArmConfig>(paper);
  const ArmConfig& b = task_config_as<ArmConfig>(quick);
  EXPECT_EQ(a.geometry.link1_length, b.geometry.link1_length);
  EXPECT_EQ(a.geometry.link2_length, b.geometry.link2_length);
  EXPECT_EQ(a.geometry.base, b.geometry.base);
  EXPECT_EQ(a.geometry.obstacles, b.geometry.obstacles);
  EXPECT_EQ(a.geometry.object, b.geometry.object);
  EXPECT_EQ(a.start_A, b.start_A);
  EXPECT_EQ(a.limits.shoulder_min_deg, b.limits.shoulder_min_deg);
  EXPECT_EQ(a.limits.shoulder_max_deg, b.limits.shoulder_max_deg);
  EXPECT_EQ(a.limits.elbow_min_deg, b.limits.elbow_min_deg);
  EXPECT_EQ(a.limits.elbow_max_deg, b.limits.elbow_max_deg);
  EXPECT_EQ(a.series, b.series);
  EXPECT_EQ(a.steps_per_series, b.steps_per_series);
  EXPECT_EQ(a.test_max_steps, b.test_max_steps);
  EXPECT_EQ(paper.runs, 30);
  EXPECT_EQ(paper.sweep.kernels.front(), 16);
}

}  // namespace
}  // namespace ggk::engine
