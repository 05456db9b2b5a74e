#pragma once
// Parameters of the Khepera task as a job file gives them (plain data; the
// engine's job-file parser fills it, the Khepera protocol reads it). Defaults are
// the paper's (sec. 4.2) and DESIGN.md's; the arena's default is an empty 1 m box
// for tests, the real one comes from the job file (jobs/arenas/default.toml).

#include <cstdint>

#include "sims/khepera/arena.hpp"
#include "sims/khepera/motion.hpp"
#include "sims/khepera/robot.hpp"
#include "sims/khepera/sensor_model.hpp"

namespace ggk::sims::khepera {

struct Rewards {
  double forward = 1.0;     // a forward step that did not collide
  double collision = -2.0;  // any step undone by a collision
  // Rotations and backward steps that do not collide give 0.
  friend bool operator==(const Rewards&, const Rewards&) = default;
};

struct KheperaConfig {
  RobotBody body;
  SensorModel sensors;
  MotionModel motion;
  Rewards rewards;
  Arena arena{.min = {0.0, 0.0},
              .max = {100.0, 100.0},
              .walled = true,
              .obstacles = {},
              .start = {50.0, 50.0, 0.0}};
  // Protocol (paper sec. 4.2): random-walk series per run, each from a random free
  // pose; random actions per series; step limit of an evaluation episode from the
  // start pose (stopped early by a collision); evaluation episodes per fit (the
  // sensors and wheels are noisy, so one episode is one draw of the return).
  std::int32_t series = 200;
  std::int32_t steps_per_series = 100;
  std::int32_t test_max_steps = 150;
  std::int32_t test_episodes = 10;
};

// Throws KheperaConfigError (khepera_config_error.hpp) for the first bad field: a
// non-finite number, a length or count out of its range (see the structs), a
// sensor mounted outside the body, a degenerate obstacle, a start outside the
// arena's box. Whether the start pose is clear of obstacles needs the compiled
// world: Khepera's constructor checks that.
void check_config(const KheperaConfig& config);

}  // namespace ggk::sims::khepera
