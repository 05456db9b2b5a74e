// The [khepera] table of job files (inline arenas and arena files, every key and
// its default, malformed tables reported at file:line and key), the shipped
// Khepera job files and the default arena.

#include "engine/tasks/khepera/khepera_table.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/job/study.hpp"
#include "engine/tasks/khepera/khepera_task.hpp"
#include "engine/tasks/khepera/khepera_test_job.hpp"
#include "engine/tasks/task_list.hpp"
#include "kernels/graph_diagnostics.hpp"
#include "kernels/shortest_paths.hpp"
#include "sims/khepera/khepera.hpp"
#include "support/job_text.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
namespace khepera = sims::khepera;
using namespace test_support;

std::string job_with(int line, const std::string& replacement) {
  return with_line(kKheperaJob, line, replacement);
}

// kKheperaJob cut before its [khepera.arena] table (so without an arena).
std::string without_arena() {
  const std::string job = kKheperaJob;
  return job.substr(0, job.find("[khepera.arena]"));
}

// kKheperaJob with arena_file = `arena_file` (line 12) instead of the inline arena.
std::string with_arena_file(const std::string& arena_file) {
  const std::string job = job_with(11, "test_episodes = 2\narena_file = \"" + arena_file + "\"");
  return job.substr(0, job.find("[khepera.arena]"));
}

const KheperaTaskConfig& khepera_config(const JobSpec& job) {
  return task_config_as<KheperaTaskConfig>(job);
}

std::string khepera_job_error(const std::string& text, const fs::path& source = "bad.toml") {
  try {
    parse_job(text, source, task_tables(), no_output_check());
  } catch (const JobError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a JobError for:\n" << text;
  return {};
}

TEST(KheperaTable, ReadsAnInlineArena) {
  const JobSpec job = parse_job(kKheperaJob, "khepera.toml", task_tables(), no_output_check());
  EXPECT_EQ(job.task, "khepera");
  ASSERT_TRUE(job.task_config.type() == typeid(KheperaTaskConfig));
  const khepera::Arena& arena = khepera_config(job).simulator.arena;
  EXPECT_EQ(arena.min, (khepera::Point2{0.0, 0.0}));
  EXPECT_EQ(arena.max, (khepera::Point2{40.0, 40.0}));
  EXPECT_TRUE(arena.walled);
  EXPECT_EQ(arena.start, (khepera::Pose{10.0, 10.0, std::numbers::pi / 2.0}));
  ASSERT_EQ(arena.obstacles.size(), 4u);
  EXPECT_EQ(std::get<khepera::Rectangle>(arena.obstacles[0]),
            (khepera::Rectangle{{20.0, 20.0}, {30.0, 30.0}}));
  EXPECT_EQ(std::get<khepera::Disc>(arena.obstacles[1]), (khepera::Disc{{10.0, 30.0}, 3.0}));
  EXPECT_EQ(std::get<khepera::Segment>(arena.obstacles[2]),
            (khepera::Segment{{40.0, 10.0}, {30.0, 10.0}}));
  EXPECT_EQ(std::get<khepera::RotatedRectangle>(arena.obstacles[3]),
            (khepera::RotatedRectangle{{5.0, 20.0}, 6.0, 2.0, 45.0}));

  // No obstacles, no walls, and a rotated rectangle's angle defaults to 0.
  const JobSpec bare = parse_job(without_arena() + R"([khepera.arena]
min = [-5, -5]
max = [5, 5]
walled = false
start = { x = 0, y = 0, heading_deg = -90 }
)",
                                 "khepera.toml", task_tables(), no_output_check());
  const khepera::Arena& open = khepera_config(bare).simulator.arena;
  EXPECT_FALSE(open.walled);
  EXPECT_TRUE(open.obstacles.empty());
  EXPECT_EQ(open.start, (khepera::Pose{0.0, 0.0, -std::numbers::pi / 2.0}));
  const JobSpec unrotated =
      parse_job(job_with(35, ""), "khepera.toml", task_tables(), no_output_check());
  EXPECT_EQ(
      std::get<khepera::RotatedRectangle>(khepera_config(unrotated).simulator.arena.obstacles[3])
          .angle_deg,
      0.0);
}

TEST(KheperaTable, DefaultsAreTheSimulatorsAndThePapers) {
  // Only the arena given: every other key takes its default.
  const std::string text = R"(name = "khepera-defaults"
task = "khepera"
runs = 1
seed = 7
[sweep]
kernels = [5]
sigma = [1000.0]
[khepera.arena]
min = [0, 0]
max = [40, 40]
start = { x = 10, y = 10, heading_deg = 0 }
)";
  const KheperaTaskConfig config =
      khepera_config(parse_job(text, "defaults.toml", task_tables(), no_output_check()));
  const khepera::KheperaConfig defaults;
  EXPECT_EQ(config.simulator.body, defaults.body);
  EXPECT_EQ(config.simulator.sensors, defaults.sensors);
  EXPECT_EQ(config.simulator.motion, defaults.motion);
  EXPECT_EQ(config.simulator.rewards, defaults.rewards);
  EXPECT_EQ(config.simulator.series, 200);
  EXPECT_EQ(config.simulator.steps_per_series, 100);
  EXPECT_EQ(config.simulator.test_max_steps, 150);
  EXPECT_EQ(config.simulator.test_episodes, 10);
  EXPECT_EQ(config.protocol.som.rows, 24);
  EXPECT_EQ(config.protocol.som.cols, 29);
  EXPECT_EQ(config.protocol.som.epochs, 30);
  EXPECT_FALSE(config.protocol.som.initial_radius.has_value());
  EXPECT_EQ(config.protocol.som.final_radius, 1.0);
  EXPECT_EQ(config.protocol.som.radius_schedule, kernels::SomRadiusSchedule::exponential);
  EXPECT_EQ(config.protocol.som.initialization, kernels::SomInitialization::principal_components);
  EXPECT_FALSE(config.protocol.som_grid_from_samples);
}

TEST(KheperaTable, ReadsEveryKey) {
  const std::string job = with_line(with_line(kKheperaJob, 14, R"(cols = 5
epochs = 12
initial_radius = 3.0
final_radius = 0.5
radius_schedule = "linear"
initialization = "random_samples")"),
                                    11, R"(test_episodes = 4
test_max_steps = 80
[khepera.robot]
radius = 3
wheel_base = 5.0
sensors = [[1.0, 1.5, 90.0], [1.3, 1.3, 45.0], [1.6, 0.6, 0.0], [1.6, -0.6, 0.0],
           [1.3, -1.3, -45.0], [1.0, -1.5, -90.0], [-1.5, -1.0, 180.0], [-2.0, 1.0, 170]]
[khepera.sensors]
range = 8.0
side_ray_deg = 10
response_m = 1000.0
response_x0 = -1.0
response_c = 6.5
noise_model = "threshold"
noise_sd = 0
detection_threshold = 30
max_reading = 1000.0
[khepera.motion]
step_cm = 1.0
turn_deg = 30
wheel_noise = 0.0
collision_substeps = 8
[khepera.rewards]
forward = 2.0
collision = -5)");
  const KheperaTaskConfig c =
      khepera_config(parse_job(job, "every.toml", task_tables(), no_output_check()));
  EXPECT_EQ(c.simulator.series, 10);
  EXPECT_EQ(c.simulator.steps_per_series, 50);
  EXPECT_EQ(c.simulator.test_episodes, 4);
  EXPECT_EQ(c.simulator.test_max_steps, 80);
  EXPECT_EQ(c.simulator.body.radius, 3.0);
  EXPECT_EQ(c.simulator.body.wheel_base, 5.0);
  EXPECT_EQ(c.simulator.body.sensors[0], (khepera::IrSensor{1.0, 1.5, 90.0}));
  EXPECT_EQ(c.simulator.body.sensors[7], (khepera::IrSensor{-2.0, 1.0, 170.0}));
  EXPECT_EQ(c.simulator.sensors,
            (khepera::SensorModel{8.0, 10.0, 1000.0, -1.0, 6.5,
                                  khepera::SensorNoiseModel::threshold, 0.04, 0.0, 30.0, 1000.0}));
  EXPECT_EQ(c.simulator.motion, (khepera::MotionModel{1.0, 30.0, 0.0, 8}));
  EXPECT_EQ(c.simulator.rewards, (khepera::Rewards{2.0, -5.0}));
  EXPECT_EQ(c.protocol.som.rows, 4);
  EXPECT_EQ(c.protocol.som.cols, 5);
  EXPECT_EQ(c.protocol.som.epochs, 12);
  EXPECT_EQ(c.protocol.som.initial_radius, 3.0);
  EXPECT_EQ(c.protocol.som.final_radius, 0.5);
  EXPECT_EQ(c.protocol.som.radius_schedule, kernels::SomRadiusSchedule::linear);
  EXPECT_EQ(c.protocol.som.initialization, kernels::SomInitialization::random_samples);

  const KheperaTaskConfig derived =
      khepera_config(parse_job(with_line(job_with(13, "grid_from_samples = true"), 14, ""),
                               "derived.toml", task_tables(), no_output_check()));
  EXPECT_TRUE(derived.protocol.som_grid_from_samples);
}

struct MalformedKhepera {
  std::string what;
  std::string text;
  std::vector<std::string> expected;  // substrings of the message
};

std::vector<MalformedKhepera> malformed_tables() {
  const std::string job = kKheperaJob;
  const std::string no_khepera = job.substr(0, job.find("[khepera]"));
  const std::string eight_sensors =
      "sensors = [[1.0, 1.5, 90.0], [1.3, 1.3, 45.0], [1.6, 0.6, 0.0], [1.6, -0.6, 0.0], "
      "[1.3, -1.3, -45.0], [1.0, -1.5, -90.0], [-1.5, -1.0, 180.0], [3.0, 1.0, 180.0]]";
  return {
      {"[khepera] missing",
       no_khepera,
       {"bad.toml: khepera: required table [khepera] is missing (task = \"khepera\")"}},
      {"[khepera] with task maze",
       job_with(2, "task = \"maze\"") + "[maze]\nmap = \"G.\"\n",
       {"bad.toml:8:2: khepera: table [khepera] belongs to task 'khepera', but task = \"maze\""}},
      {"task misspelt",
       job_with(2, "task = \"kepera\""),
       {"bad.toml:2:1: task:", "got \"kepera\"; did you mean 'khepera'?"}},
      {"unknown key with suggestion",
       job_with(11, "test_episode = 2"),
       {"bad.toml:11:1: [khepera] test_episode: unknown key; did you mean 'test_episodes'?"}},
      {"unknown sub-table with suggestion",
       job + "[khepera.sensor]\nrange = 5.0\n",
       {"bad.toml:", "[khepera] sensor: unknown key; did you mean 'sensors'?"}},
      {"series of the wrong type",
       job_with(9, "series = \"10\""),
       {"bad.toml:9:1: [khepera] series: expected an integer >= 1, got \"10\""}},
      {"test_episodes = 0",
       job_with(11, "test_episodes = 0"),
       {"bad.toml:11:1: [khepera] test_episodes: expected an integer in [1, 10000], got 0"}},
      {"test_episodes that never end",
       job_with(11, "test_episodes = 2147483647"),
       {"bad.toml:11:1: [khepera] test_episodes: expected an integer in [1, 10000], got "
        "2147483647"}},
      {"test_max_steps that never end",
       job_with(11, "test_max_steps = 2147483647"),
       {"bad.toml:11:1: [khepera] test_max_steps: expected an integer in [1, 1000000], got "
        "2147483647"}},
      {"too many readings",
       with_line(job_with(9, "series = 100000"), 10, "steps_per_series = 100000"),
       {"bad.toml:10:1: [khepera] steps_per_series:", "10000100000 readings per run"}},
      {"no arena",
       without_arena(),
       {"bad.toml:8:1: khepera: the arena is missing", "arena_file", "[khepera.arena]"}},
      {"both arena and arena_file",
       job_with(11, "test_episodes = 2\narena_file = \"arenas/default.toml\""),
       {"bad.toml:12:1: [khepera] arena_file: give either arena_file or a [khepera.arena] table, "
        "not both"}},
      {"arena_file a table",
       without_arena() + "[khepera.arena_file]\n",
       {"bad.toml:", "[khepera] arena_file: expected a string, got a table"}},
      {"arena file that does not exist",
       with_arena_file("nope.toml"),
       {"bad.toml:12:1: [khepera] arena_file: arena file 'nope.toml' (nope.toml) does not "
        "exist"}},
      {"arena not a table",
       with_line(without_arena(), 11, "test_episodes = 2\narena = 5"),
       {"bad.toml:12:1: [khepera] arena: expected a table, got 5"}},
      {"arena box inverted",
       job_with(17, "max = [40.0, -1.0]"),
       {"bad.toml:17:1: [khepera.arena] max: expected max > min in both coordinates"}},
      {"arena corner a string",
       job_with(16, "min = [0.0, \"0\"]"),
       {"bad.toml:16:13: [khepera.arena] min: expected a finite number for y, got \"0\""}},
      {"arena unknown key",
       job_with(16, "min = [0.0, 0.0]\nwall = true"),
       {"bad.toml:17:1: [khepera.arena] wall: unknown key; did you mean 'walled'?"}},
      {"start missing",
       job_with(18, ""),
       {"bad.toml:15:1: [khepera.arena] start: required key is missing"}},
      {"start heading missing",
       job_with(18, "start = { x = 10.0, y = 10.0 }"),
       {"bad.toml:18:9: [khepera.arena.start] heading_deg: required key is missing"}},
      {"start heading in radians",
       job_with(18, "start = { x = 10.0, y = 10.0, heading = 1.5 }"),
       {"bad.toml:18:31: [khepera.arena.start] heading: unknown key; did you mean "
        "'heading_deg'?"}},
      {"start pose inside an obstacle",
       job_with(18, "start = { x = 25.0, y = 25.0, heading_deg = 0.0 }"),
       {"bad.toml:18:1: [khepera.arena] start: khepera: the body overlaps a wall or an obstacle "
        "at the start pose"}},
      {"start pose grazing a disc",
       job_with(18, "start = { x = 10.0, y = 26.0, heading_deg = 0.0 }"),
       {"bad.toml:18:1: [khepera.arena] start:", "overlaps"}},
      {"start pose against a wall",
       job_with(18, "start = { x = 1.0, y = 10.0, heading_deg = 0.0 }"),
       {"bad.toml:18:1: [khepera.arena] start:", "overlaps"}},
      {"start pose outside the box",
       job_with(18, "start = { x = 50.0, y = 10.0, heading_deg = 0.0 }"),
       {"bad.toml:18:1: [khepera.arena] start:", "inside the arena box"}},
      {"bad obstacle kind",
       job_with(20, "kind = \"rectangel\""),
       {"bad.toml:20:1: [khepera.arena.obstacles[0]] kind: expected one of 'segment', "
        "'rectangle', 'rotated_rectangle', or 'disc', got \"rectangel\"; did you mean "
        "'rectangle'?"}},
      {"obstacle kind missing",
       job_with(20, ""),
       {"bad.toml:19:1: [khepera.arena.obstacles[0]] kind: required key is missing"}},
      {"rectangle with a radius",
       job_with(20, "kind = \"rectangle\"\nradius = 1.0"),
       {"bad.toml:21:1: [khepera.arena.obstacles[0]] radius: a rectangle has no key 'radius' "
        "(its keys: kind, min, max)"}},
      {"rectangle min above max",
       job_with(22, "max = [30.0, 20.0]"),
       {"bad.toml:22:1: [khepera.arena.obstacles[0]] max: expected max > min"}},
      {"negative disc radius",
       job_with(26, "radius = -3.0"),
       {"bad.toml:26:1: [khepera.arena.obstacles[1]] radius: expected a number > 0.0, got -3.0"}},
      {"segment of one point",
       job_with(30, "b = [40, 10]"),
       {"bad.toml:30:1: [khepera.arena.obstacles[2]] b: expected the segment's ends a and b to "
        "differ"}},
      {"segment with three coordinates",
       job_with(29, "a = [40.0, 10.0, 0.0]"),
       {"bad.toml:29:1: [khepera.arena.obstacles[2]] a: expected an array of 2 numbers [x, y], "
        "got an array of 3 elements"}},
      {"rotated rectangle of width 0",
       job_with(34, "size = [0, 2.0]"),
       {"bad.toml:34:9: [khepera.arena.obstacles[3]] size: expected a length > 0.0 for width, "
        "got 0"}},
      {"rotated rectangle with a disc's key",
       job_with(35, "angle_deg = 45.0\ncentre = [1, 1]"),
       {"bad.toml:36:1: [khepera.arena.obstacles[3]] centre: unknown key; did you mean "
        "'center'?"}},
      {"obstacles not tables",
       without_arena() + "[khepera.arena]\nmin = [0, 0]\nmax = [40, 40]\nstart = { x = 10, y = 10, "
                         "heading_deg = 0 }\nobstacles = [2]\n",
       {"bad.toml:19:14: [khepera.arena] obstacles: expected a table", "got 2"}},
      {"som rows = 0",
       job_with(13, "rows = 0"),
       {"bad.toml:13:1: [khepera.som] rows: expected an integer >= 1, got 0"}},
      {"som larger than the samples",
       with_line(job_with(13, "rows = 30"), 14, "cols = 30"),
       {"bad.toml:13:1: [khepera.som] rows: rows x cols = 30 x 30 = 900 units, more than the 510 "
        "readings per run"}},
      {"default som larger than the samples",
       with_line(with_line(job_with(12, ""), 13, ""), 14, ""),
       {"bad.toml:10:1: [khepera] steps_per_series: rows x cols = 24 x 29 = 696 units",
        "set [khepera.som] rows and cols, or grid_from_samples = true"}},
      {"som key misspelt",
       job_with(13, "row = 4"),
       {"bad.toml:13:1: [khepera.som] row: unknown key; did you mean 'rows'?"}},
      {"som schedule unknown",
       job_with(14, "cols = 5\nradius_schedule = \"exp\""),
       {"bad.toml:15:1: [khepera.som] radius_schedule: expected one of 'exponential' or "
        "'linear', got \"exp\"; did you mean 'exponential'?"}},
      {"som initialisation unknown",
       job_with(14, "cols = 5\ninitialization = \"pca\""),
       {"bad.toml:15:1: [khepera.som] initialization:", "got \"pca\""}},
      {"som initial radius below the final one",
       job_with(14, "cols = 5\ninitial_radius = 0.5"),
       {"bad.toml:15:1: [khepera.som] initial_radius: expected a number >= final_radius (1.0, "
        "its default), got 0.5"}},
      {"som epochs a float",
       job_with(14, "cols = 5\nepochs = 10.0"),
       {"bad.toml:15:1: [khepera.som] epochs: expected an integer in [1, 10000], got 10.0"}},
      {"som epochs that never end",
       job_with(14, "cols = 5\nepochs = 2147483647"),
       {"bad.toml:15:1: [khepera.som] epochs: expected an integer in [1, 10000], got "
        "2147483647"}},
      {"som grid given and derived",
       job_with(14, "cols = 5\ngrid_from_samples = true"),
       {"bad.toml:13:1: [khepera.som] rows: the grid is derived from the samples"}},
      {"negative robot radius",
       job + "[khepera.robot]\nradius = -1.0\n",
       {"bad.toml:37:1: [khepera.robot] radius: expected a number > 0.0, got -1.0"}},
      {"robot too small for its sensors",
       job + "[khepera.robot]\nradius = 1.5\n",
       {"bad.toml:37:1: [khepera.robot] radius: khepera: sensor", "strictly inside the body"}},
      {"one sensor",
       job + "[khepera.robot]\nsensors = [[1.0, 1.5, 90.0]]\n",
       {"bad.toml:37:1: [khepera.robot] sensors: expected an array of 8 arrays [x, y, "
        "heading_deg] (s0..s7), got an array of 1 element"}},
      {"sensor outside the body",
       job + "[khepera.robot]\n" + eight_sensors + "\n",
       {"bad.toml:37:144: [khepera.robot] sensors: khepera: sensor 7: must be mounted strictly "
        "inside the body disc"}},
      {"sensor with two numbers",
       job + "[khepera.robot]\nsensors = [[1.0, 1.5], 1, 2, 3, 4, 5, 6, 7]\n",
       {"bad.toml:37:12: [khepera.robot] sensors: expected sensor s0 as [x, y, heading_deg], got "
        "an array of 2 elements"}},
      {"sensor response with a pole",
       job + "[khepera.sensors]\nresponse_c = 0.5\n",
       {"bad.toml:37:1: [khepera.sensors] response_c: khepera: response c must exceed x0^2"}},
      {"side rays at 90 degrees",
       job + "[khepera.sensors]\nside_ray_deg = 90\n",
       {"bad.toml:37:1: [khepera.sensors] side_ray_deg: expected a number in [0.0, 90.0), got "
        "90"}},
      {"negative noise",
       job + "[khepera.sensors]\nnoise_model = \"additive\"\nnoise_sd = -1\n",
       {"bad.toml:38:1: [khepera.sensors] noise_sd: expected a number >= 0.0, got -1"}},
      {"negative noise fraction",
       job + "[khepera.sensors]\nnoise_fraction = -0.1\n",
       {"bad.toml:37:1: [khepera.sensors] noise_fraction: expected a number >= 0.0, got -0.1"}},
      {"unknown noise model",
       job + "[khepera.sensors]\nnoise_model = \"proportionnal\"\n",
       {"bad.toml:37:1: [khepera.sensors] noise_model:"}},
      {"noise sd under the default proportional model",
       job + "[khepera.sensors]\nnoise_sd = 20\n",
       {"bad.toml:37:1: [khepera.sensors] noise_sd: applies only to noise_model = \"threshold\" "
        "or \"additive\"; noise_model is \"proportional\" (the default)"}},
      {"noise fraction under the additive model",
       job + "[khepera.sensors]\nnoise_model = \"additive\"\nnoise_fraction = 0.1\n",
       {"bad.toml:38:1: [khepera.sensors] noise_fraction: applies only to noise_model = "
        "\"proportional\"; noise_model is \"additive\""}},
      {"detection threshold without the threshold model",
       job + "[khepera.sensors]\nnoise_model = \"additive\"\ndetection_threshold = 60\n",
       {"bad.toml:38:1: [khepera.sensors] detection_threshold: applies only to noise_model = "
        "\"threshold\"; noise_model is \"additive\""}},
      {"negative detection threshold",
       job + "[khepera.sensors]\nnoise_model = \"threshold\"\ndetection_threshold = -1\n",
       {"bad.toml:38:1: [khepera.sensors] detection_threshold: expected a number >= 0.0, got -1"}},
      {"half-turn rotations",
       job + "[khepera.motion]\nturn_deg = 180\n",
       {"bad.toml:37:1: [khepera.motion] turn_deg: expected a number in (0.0, 180.0), got 180"}},
      {"no collision sub-steps",
       job + "[khepera.motion]\ncollision_substeps = 0\n",
       {"bad.toml:37:1: [khepera.motion] collision_substeps: expected an integer in [1, 1000], "
        "got 0"}},
      {"wheel noise of 100 %",
       job + "[khepera.motion]\nwheel_noise = 1.0\n",
       {"bad.toml:37:1: [khepera.motion] wheel_noise: expected a number in [0.0, 1.0), got 1.0"}},
      {"reward a string",
       job + "[khepera.rewards]\nforward = \"one\"\n",
       {"bad.toml:37:1: [khepera.rewards] forward: expected a number, got \"one\""}},
      {"reward not finite",
       job + "[khepera.rewards]\ncollision = -inf\n",
       {"bad.toml:37:1: [khepera.rewards] collision: expected a number, got -inf"}},
  };
}

TEST(KheperaTable, RejectsMalformedTables) {
  const std::vector<MalformedKhepera> cases = malformed_tables();
  EXPECT_GE(cases.size(), 15u);
  for (const MalformedKhepera& job : cases) {
    const std::string message = khepera_job_error(job.text);
    for (const std::string& part : job.expected) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "case '" << job.what << "': the message\n  " << message << "\nlacks\n  " << part;
    }
  }
}

// Arena files in a scratch folder.
class KheperaArenaFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("ggk_khepera_table_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "arenas");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const fs::path& relative, const std::string& text) const {
    std::ofstream(dir_ / relative) << text;
  }

  fs::path dir_;
};

constexpr const char* kArenaFile = R"(# a test arena
min = [0.0, 0.0]
max = [40.0, 40.0]
walled = true
start = { x = 10.0, y = 10.0, heading_deg = 180.0 }
[[obstacles]]
kind = "disc"
center = [30.0, 30.0]
radius = 4.0
)";

TEST_F(KheperaArenaFile, IsReadRelativeToTheJobFile) {
  write("arenas/test.toml", kArenaFile);
  const JobSpec job = parse_job(with_arena_file("arenas/test.toml"), dir_ / "job.toml",
                                task_tables(), no_output_check());
  const khepera::Arena& arena = khepera_config(job).simulator.arena;
  EXPECT_EQ(arena.max, (khepera::Point2{40.0, 40.0}));
  EXPECT_EQ(arena.start, (khepera::Pose{10.0, 10.0, std::numbers::pi}));
  ASSERT_EQ(arena.obstacles.size(), 1u);
  EXPECT_EQ(std::get<khepera::Disc>(arena.obstacles[0]), (khepera::Disc{{30.0, 30.0}, 4.0}));
  // The protocol keys of the job still apply.
  EXPECT_EQ(khepera_config(job).simulator.series, 10);
}

TEST_F(KheperaArenaFile, ErrorsNameTheArenaFileItsLineAndTheJob) {
  const std::string arena_path = (dir_ / "arenas" / "bad.toml").string();
  const std::string job_path = (dir_ / "job.toml").string();
  const std::string job_reading_bad = with_arena_file("arenas/bad.toml");
  struct Case {
    std::string what;
    std::string arena;
    std::string expected;
  };
  const std::string text = kArenaFile;
  const std::vector<Case> cases = {
      {"unknown key", text + "wall = 1\n", ":10:1: [obstacles[0]] wall: unknown key"},
      {"unknown top-level key", "wall = true\n" + text,
       ":1:1: wall: unknown key; did you mean 'walled'?"},
      {"bad kind", std::string(text).replace(text.find("\"disc\""), 6, "\"circle\""),
       ":7:1: [obstacles[0]] kind: expected one of"},
      {"start inside the disc",
       std::string(text).replace(text.find("x = 10.0, y = 10.0"), 18, "x = 30.0, y = 27.0"),
       ":5:1: start: khepera: the body overlaps"},
      {"syntax error", text + "radius = = 2\n", ":10:"},
  };
  for (const Case& c : cases) {
    write("arenas/bad.toml", c.arena);
    const std::string message = khepera_job_error(job_reading_bad, dir_ / "job.toml");
    EXPECT_EQ(message.rfind(arena_path + c.expected, 0), 0u)
        << "case '" << c.what << "': " << message;
    EXPECT_NE(message.find("(the arena_file of '" + job_path + "')"), std::string::npos)
        << "case '" << c.what << "': " << message;
  }
}

TEST_F(KheperaArenaFile, MissingFilesAreReportedAtTheKey) {
  const std::string job = with_arena_file("arenas/missing.toml");
  EXPECT_NE(khepera_job_error(job, dir_ / "job.toml")
                .find(":12:1: [khepera] arena_file: arena file 'arenas/missing.toml' (" +
                      (dir_ / "arenas" / "missing.toml").string() + ") does not exist"),
            std::string::npos);
  EXPECT_NE(khepera_job_error(with_arena_file("arenas"), dir_ / "job.toml").find("is a directory"),
            std::string::npos);
  EXPECT_NE(khepera_job_error(with_arena_file(""), dir_ / "job.toml")
                .find(":12:1: [khepera] arena_file: expected a file name, got \"\""),
            std::string::npos);
}

// The shipped job files and the default arena.
class ShippedKheperaJob : public ::testing::Test {
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

TEST_F(ShippedKheperaJob, DefaultArenaParsesIntoItsShapes) {
  const JobSpec job = load("khepera-paper");
  const khepera::Arena& arena = khepera_config(job).simulator.arena;
  EXPECT_EQ(arena.min, (khepera::Point2{0.0, 0.0}));
  EXPECT_EQ(arena.max, (khepera::Point2{80.0, 80.0}));
  EXPECT_TRUE(arena.walled);
  EXPECT_EQ(arena.start, (khepera::Pose{21.0, 36.0, std::numbers::pi / 2.0}));
  ASSERT_EQ(arena.obstacles.size(), 6u);
  using khepera::Disc;
  using khepera::Rectangle;
  EXPECT_EQ(std::get<Rectangle>(arena.obstacles[0]), (Rectangle{{14.0, 50.0}, {28.0, 58.0}}));
  EXPECT_EQ(std::get<Rectangle>(arena.obstacles[1]), (Rectangle{{12.0, 10.0}, {26.0, 22.0}}));
  EXPECT_EQ(std::get<Disc>(arena.obstacles[2]), (Disc{{38.0, 18.0}, 4.0}));
  EXPECT_EQ(std::get<Disc>(arena.obstacles[3]), (Disc{{62.0, 38.0}, 7.0}));
  EXPECT_EQ(std::get<khepera::RotatedRectangle>(arena.obstacles[4]),
            (khepera::RotatedRectangle{{54.0, 63.0}, 22.0, 5.0, 30.0}));
  EXPECT_EQ(std::get<khepera::Segment>(arena.obstacles[5]),
            (khepera::Segment{{80.0, 18.0}, {64.0, 18.0}}));
  // The start pose is free and faces the first block (north), 11.4 cm ahead of
  // the body: 7 forward steps of 1.5 cm fit, the eighth collides.
  const khepera::Khepera robot(khepera_config(job).simulator);
  EXPECT_FALSE(robot.collides(robot.start_pose()));
  khepera::Pose pose = robot.start_pose();
  for (int step = 0; step < 7; ++step) {
    pose.y += 1.5;
    EXPECT_FALSE(robot.collides(pose)) << "step " << step;
  }
  pose.y += 1.5;
  EXPECT_TRUE(robot.collides(pose));
}

TEST_F(ShippedKheperaJob, PaperQuickAndCiJobs) {
  const JobSpec paper = load("khepera-paper");
  EXPECT_EQ(paper.task, "khepera");
  EXPECT_EQ(paper.runs, 20);
  EXPECT_EQ(paper.sweep.kernels,
            (std::vector<std::int32_t>{10, 20, 30, 40, 50, 60, 70, 80, 90, 100}));
  EXPECT_EQ(paper.sweep.sigma, std::vector<double>{1000.0});
  EXPECT_EQ(paper.sweep.basis,
            (std::vector<KernelType>{KernelType::ggk, KernelType::ogk, KernelType::pvf}));
  EXPECT_EQ(paper.basis.scheme, kernels::BasisScheme::copy);
  const KheperaTaskConfig& p = khepera_config(paper);
  EXPECT_EQ(p.simulator.series * p.simulator.steps_per_series, 20000);
  EXPECT_EQ(p.simulator.test_max_steps, 150);
  EXPECT_EQ(p.protocol.som.rows * p.protocol.som.cols, 696);

  for (const char* name : {"khepera-quick", "ci-khepera"}) {
    SCOPED_TRACE(name);
    const JobSpec job = load(name);
    EXPECT_EQ(job.task, "khepera");
    EXPECT_EQ(job.basis.scheme, kernels::BasisScheme::copy);
    EXPECT_EQ(job.sweep.sigma, std::vector<double>{1000.0});
    const KheperaTaskConfig& c = khepera_config(job);
    EXPECT_EQ(c.simulator.arena.min, p.simulator.arena.min);
    EXPECT_EQ(c.simulator.arena.max, p.simulator.arena.max);
    EXPECT_EQ(c.simulator.arena.start, p.simulator.arena.start);
    EXPECT_TRUE(c.simulator.arena.obstacles == p.simulator.arena.obstacles);
    EXPECT_EQ(c.simulator.body, p.simulator.body);
    EXPECT_EQ(c.simulator.sensors, p.simulator.sensors);
    EXPECT_EQ(c.simulator.motion, p.simulator.motion);
    EXPECT_EQ(c.simulator.rewards, p.simulator.rewards);
  }

  // The study files (jobs/khepera-study.toml, khepera-widths-study.toml, the
  // claim map): each configuration is the paper job but for its study values
  // (and the name and output), every key compared by its resolved value.
  const auto study = [&](const std::string& name) {
    return load_study(jobs_ / (name + ".toml"), task_tables(), no_output_check());
  };
  const std::set<std::string> kNotTheJob = {"name", "output.file"};
  const auto differs_only_in = [&](const RunConfiguration& configuration,
                                   std::set<std::string> keys) {
    keys.insert(kNotTheJob.begin(), kNotTheJob.end());
    return paper.resolved.difference(configuration.job.resolved, "paper", "study", keys);
  };
  const Study rotation = study("khepera-study");
  ASSERT_EQ(rotation.configurations.size(), 3u);
  for (std::size_t c = 0; c < 3; ++c) {
    const RunConfiguration& configuration = rotation.configurations[c];
    SCOPED_TRACE(configuration.job.configuration_group);
    EXPECT_EQ(khepera_config(configuration.job).simulator.motion.turn_deg,
              15.0 * static_cast<double>(c + 1));
    EXPECT_EQ(differs_only_in(configuration, {"khepera.motion.turn_deg"}), std::nullopt);
  }
  // The 15-degree configuration is the paper job, key for key.
  EXPECT_EQ(differs_only_in(rotation.configurations[0], {}), std::nullopt);

  // The widths study: two rotation steps, the widths on the built-in axis.
  const Study widths = study("khepera-widths-study");
  ASSERT_EQ(widths.configurations.size(), 2u);
  EXPECT_EQ(widths.job().sweep.sigma, (std::vector<double>{250.0, 500.0, 1000.0, 2000.0}));
  EXPECT_EQ(khepera_config(widths.configurations[1].job).simulator.motion.turn_deg, 45.0);
  EXPECT_TRUE(khepera_config(widths.configurations[1].job).simulator.arena.obstacles ==
              p.simulator.arena.obstacles);

  // The claim map: 3 steps x 3 noise models, each model at its default level.
  const Study map = study("khepera-claim-map");
  ASSERT_EQ(map.configurations.size(), 9u);
  EXPECT_EQ(map.job().runs, paper.runs);
  EXPECT_EQ(map.job().seed, paper.seed);
  EXPECT_EQ(khepera_config(map.configurations[4].job).simulator.motion.turn_deg, 30.0);
  EXPECT_EQ(khepera_config(map.configurations[0].job).simulator.sensors,
            p.simulator.sensors);  // 15 degrees, proportional: the paper's sensors
}

}  // namespace
}  // namespace ggk::engine
