#pragma once
// Parameters of the arm task as a job file gives them (plain data; the engine's
// job-file parser fills it, the arm protocol reads it). Defaults are the paper's
// joint grid and protocol; the geometry has no default (jobs/arm-paper.toml).

#include <cstdint>
#include <string>

#include "sims/arm/arm_geometry.hpp"

namespace ggk::sims::arm {

// Grid angles are counted in tenths of a degree (exact integers), so that a step
// of 2.5 degrees is as exact as one of 5: every grid angle is min + i * step.
inline constexpr std::int32_t kTenthsPerDegree = 10;
// The paper's joint grid step, 5 degrees (sec. 4.1), in tenths of a degree.
inline constexpr std::int32_t kPaperGridStepTenths = 50;
// The unit of the state vector: joint angles in degrees / 5, whatever the grid
// step, so that kernel widths and graph distances keep their meaning in degrees
// (1 unit = 5 degrees) when the grid gets finer.
inline constexpr std::int32_t kJointUnitDegrees = 5;

// A step in tenths of a degree as a job file writes it in degrees: "5", "2.5".
inline std::string grid_step_text(std::int32_t step_tenths) {
  std::string text = std::to_string(step_tenths / kTenthsPerDegree);
  if (step_tenths % kTenthsPerDegree != 0)
    text += "." + std::to_string(step_tenths % kTenthsPerDegree);
  return text;
}

// A pose in degrees. On the joint grid both angles are multiples of the grid
// step (exact in binary for steps that are multiples of 0.5 degree).
struct JointAngles {
  double shoulder_deg = 0.0;
  double elbow_deg = 0.0;
  friend bool operator==(const JointAngles&, const JointAngles&) = default;
};

// Hard joint limits in whole degrees, inclusive, multiples of the grid step,
// min <= max and max - min < 360 (no wrap: the two ends are distinct poses).
struct JointLimits {
  std::int32_t shoulder_min_deg = 0;
  std::int32_t shoulder_max_deg = 180;  // 37 shoulder values at 5 degrees
  std::int32_t elbow_min_deg = -180;
  std::int32_t elbow_max_deg = 175;  // 72 elbow values at 5 degrees
};

struct ArmConfig {
  ArmGeometry geometry;
  JointLimits limits;
  // Every action turns one joint by one grid step; tenths of a degree, >= 1.
  std::int32_t grid_step_tenths = kPaperGridStepTenths;
  JointAngles start_A;                   // the test start 'A' of Figs. 1(b) and 2, on the grid
  std::int32_t series = 50;              // random-walk series per run
  std::int32_t steps_per_series = 1000;  // random moves per series
  std::int32_t test_max_steps = 100;     // step limit when testing a greedy policy
};

}  // namespace ggk::sims::arm
