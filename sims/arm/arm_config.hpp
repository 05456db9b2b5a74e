#pragma once
// Parameters of the arm task as a job file gives them (plain data; the engine's
// job-file parser fills it, the arm protocol reads it). Defaults are the paper's
// joint grid and protocol; the geometry has no default (jobs/arm-paper.toml).

#include <cstdint>

#include "sims/arm/arm_geometry.hpp"

namespace ggk::sims::arm {

// Every action turns one joint by this many degrees (paper sec. 4.1).
inline constexpr std::int32_t kStepDegrees = 5;

// A pose on the joint grid, in whole degrees (multiples of kStepDegrees).
struct JointAngles {
  std::int32_t shoulder_deg = 0;
  std::int32_t elbow_deg = 0;
  friend bool operator==(const JointAngles&, const JointAngles&) = default;
};

// Hard joint limits in degrees, inclusive, multiples of kStepDegrees, min <= max
// and max - min < 360 (no wrap: the two ends are distinct poses).
struct JointLimits {
  std::int32_t shoulder_min_deg = 0;
  std::int32_t shoulder_max_deg = 180;  // 37 shoulder values
  std::int32_t elbow_min_deg = -180;
  std::int32_t elbow_max_deg = 175;  // 72 elbow values
};

struct ArmConfig {
  ArmGeometry geometry;
  JointLimits limits;
  JointAngles start_A;                   // the test start 'A' of Figs. 1(b) and 2
  std::int32_t series = 50;              // random-walk series per run
  std::int32_t steps_per_series = 1000;  // random moves per series
  std::int32_t test_max_steps = 100;     // step limit when testing a greedy policy
};

}  // namespace ggk::sims::arm
