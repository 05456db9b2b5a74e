#include "sims/arm/arm.hpp"

#include <cstddef>
#include <stdexcept>
#include <string>

#include "sims/arm/arm_config_error.hpp"
#include "sims/arm/collision.hpp"

namespace ggk::sims::arm {
namespace {

constexpr std::array<std::string_view, kNumActions> kActionNames = {"shoulder+", "shoulder-",
                                                                    "elbow+", "elbow-"};
constexpr std::array<std::int32_t, kNumActions> kShoulderDelta = {1, -1, 0, 0};
constexpr std::array<std::int32_t, kNumActions> kElbowDelta = {0, 0, 1, -1};

// Number of grid values in [min_deg, max_deg]; throws for a bad range.
std::int32_t grid_steps(std::int32_t min_deg, std::int32_t max_deg, ArmConfigField field,
                        const std::string& joint) {
  const auto fail = [&](const std::string& why) {
    throw ArmConfigError(field, -1,
                         "arm " + joint + " limits [" + std::to_string(min_deg) + ", " +
                             std::to_string(max_deg) + "] " + why);
  };
  if (min_deg % kStepDegrees != 0 || max_deg % kStepDegrees != 0) {
    fail("are not multiples of " + std::to_string(kStepDegrees) + " degrees");
  }
  const std::int64_t span = static_cast<std::int64_t>(max_deg) - min_deg;
  if (span < 0) fail("have min > max");
  // No wrap-around: min and max + 5 must be distinct poses.
  if (span >= 360) fail("span 360 degrees or more");
  return static_cast<std::int32_t>(span / kStepDegrees + 1);
}

}  // namespace

std::string_view action_name(std::int32_t action) {
  Arm::check_action(action);
  return kActionNames[static_cast<std::size_t>(action)];
}

Arm::Arm(const ArmConfig& config) : config_(config) {
  check_geometry(config_.geometry);
  const JointLimits& limits = config_.limits;
  shoulder_steps_ = grid_steps(limits.shoulder_min_deg, limits.shoulder_max_deg,
                               ArmConfigField::shoulder_limits, "shoulder");
  elbow_steps_ =
      grid_steps(limits.elbow_min_deg, limits.elbow_max_deg, ArmConfigField::elbow_limits, "elbow");

  // The collision/goal grid, once: every later query is a table look-up.
  state_at_.assign(static_cast<std::size_t>(shoulder_steps_) * elbow_steps_, kNoState);
  for (std::int32_t i = 0; i < shoulder_steps_; ++i) {
    for (std::int32_t j = 0; j < elbow_steps_; ++j) {
      const ArmPose pose =
          forward_kinematics(config_.geometry, limits.shoulder_min_deg + kStepDegrees * i,
                             limits.elbow_min_deg + kStepDegrees * j);
      if (arm_collides(config_.geometry, pose)) continue;
      const auto state = static_cast<std::int32_t>(cells_.size());
      state_at_[static_cast<std::size_t>(i) * elbow_steps_ + j] = state;
      cells_.push_back({i, j});
      const bool goal = touches_object(config_.geometry, pose);
      goal_.push_back(goal ? 1 : 0);
      if (goal) goal_states_.push_back(state);
    }
  }
  if (cells_.empty()) {
    throw ArmConfigError(ArmConfigField::obstacles, -1,
                         "arm: every pose on the joint grid collides with an obstacle");
  }
  if (goal_states_.empty()) {
    throw ArmConfigError(ArmConfigField::object, -1,
                         "arm: no collision-free pose on the joint grid puts the end effector on "
                         "the object");
  }

  const JointAngles& a = config_.start_A;
  const std::string shown =
      "arm start A (" + std::to_string(a.shoulder_deg) + ", " + std::to_string(a.elbow_deg) + ")";
  const auto fail_start = [&](const std::string& why) {
    throw ArmConfigError(ArmConfigField::start_A, -1, shown + why);
  };
  if (a.shoulder_deg % kStepDegrees != 0 || a.elbow_deg % kStepDegrees != 0) {
    fail_start(" is not on the " + std::to_string(kStepDegrees) + "-degree grid");
  }
  if (a.shoulder_deg < limits.shoulder_min_deg || a.shoulder_deg > limits.shoulder_max_deg ||
      a.elbow_deg < limits.elbow_min_deg || a.elbow_deg > limits.elbow_max_deg) {
    fail_start(" is outside the joint limits");
  }
  start_state_A_ = state_of((a.shoulder_deg - limits.shoulder_min_deg) / kStepDegrees,
                            (a.elbow_deg - limits.elbow_min_deg) / kStepDegrees);
  if (start_state_A_ == kNoState) fail_start(" collides with an obstacle");
  if (is_goal(start_state_A_)) fail_start(" is already a goal (the end effector is on the object)");
}

std::int32_t Arm::state_of(std::int32_t i_shoulder, std::int32_t i_elbow) const {
  if (i_shoulder < 0 || i_shoulder >= shoulder_steps_ || i_elbow < 0 || i_elbow >= elbow_steps_) {
    return kNoState;
  }
  return state_at_[static_cast<std::size_t>(i_shoulder) * elbow_steps_ + i_elbow];
}

bool Arm::collides(std::int32_t i_shoulder, std::int32_t i_elbow) const {
  if (i_shoulder < 0 || i_shoulder >= shoulder_steps_ || i_elbow < 0 || i_elbow >= elbow_steps_) {
    throw std::out_of_range("arm grid cell (" + std::to_string(i_shoulder) + ", " +
                            std::to_string(i_elbow) + ") is not on the " +
                            std::to_string(shoulder_steps_) + " x " + std::to_string(elbow_steps_) +
                            " grid");
  }
  return state_of(i_shoulder, i_elbow) == kNoState;
}

void Arm::check_state(std::int32_t state) const {
  if (state < 0 || state >= num_states()) {
    throw std::out_of_range("arm state " + std::to_string(state) + " is not in [0, " +
                            std::to_string(num_states()) + ")");
  }
}

void Arm::check_action(std::int32_t action) {
  if (action < 0 || action >= kNumActions) {
    throw std::out_of_range("arm action " + std::to_string(action) + " is not in [0, " +
                            std::to_string(kNumActions) + ")");
  }
}

GridCell Arm::cell_of(std::int32_t state) const {
  check_state(state);
  return cells_[static_cast<std::size_t>(state)];
}

JointAngles Arm::angles_of(std::int32_t state) const {
  const GridCell cell = cell_of(state);
  return {config_.limits.shoulder_min_deg + kStepDegrees * cell.shoulder,
          config_.limits.elbow_min_deg + kStepDegrees * cell.elbow};
}

ArmPose Arm::pose_of(std::int32_t state) const {
  const JointAngles angles = angles_of(state);
  return forward_kinematics(config_.geometry, angles.shoulder_deg, angles.elbow_deg);
}

bool Arm::is_goal(std::int32_t state) const {
  check_state(state);
  return goal_[static_cast<std::size_t>(state)] != 0;
}

std::array<double, 2> Arm::state_vector(std::int32_t state) const {
  const JointAngles angles = angles_of(state);
  return {static_cast<double>(angles.shoulder_deg) / kStepDegrees,
          static_cast<double>(angles.elbow_deg) / kStepDegrees};
}

kernels::RowMatrixXd Arm::state_vectors() const {
  kernels::RowMatrixXd vectors(num_states(), 2);
  for (std::int32_t s = 0; s < num_states(); ++s) {
    const std::array<double, 2> v = state_vector(s);
    vectors(s, 0) = v[0];
    vectors(s, 1) = v[1];
  }
  return vectors;
}

std::int32_t Arm::move(std::int32_t state, std::int32_t action) const {
  const GridCell cell = cell_of(state);
  check_action(action);
  const auto a = static_cast<std::size_t>(action);
  const std::int32_t next =
      state_of(cell.shoulder + kShoulderDelta[a], cell.elbow + kElbowDelta[a]);
  return next == kNoState ? state : next;
}

StepResult Arm::step(std::int32_t state, std::int32_t action) const {
  StepResult result;
  result.next_state = move(state, action);
  result.terminal = is_goal(result.next_state);
  result.reward = result.terminal && !is_goal(state) ? 1.0 : 0.0;
  return result;
}

}  // namespace ggk::sims::arm
