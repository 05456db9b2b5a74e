#include "sims/arm/arm.hpp"

#include <cmath>
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
constexpr std::int64_t kMaxLimitDegrees = 100000;

// Number of grid values in [min_deg, max_deg] at a step of step_tenths; throws
// for a bad range.
std::int32_t grid_steps(std::int32_t min_deg, std::int32_t max_deg, std::int32_t step_tenths,
                        ArmConfigField field, const std::string& joint) {
  const auto fail = [&](const std::string& why) {
    throw ArmConfigError(field, -1,
                         "arm " + joint + " limits [" + std::to_string(min_deg) + ", " +
                             std::to_string(max_deg) + "] " + why);
  };
  // Grid angles are int32 tenths of a degree.
  if (std::abs(static_cast<std::int64_t>(min_deg)) > kMaxLimitDegrees ||
      std::abs(static_cast<std::int64_t>(max_deg)) > kMaxLimitDegrees) {
    fail("are not within [-" + std::to_string(kMaxLimitDegrees) + ", " +
         std::to_string(kMaxLimitDegrees) + "] degrees");
  }
  const std::int64_t min_tenths = static_cast<std::int64_t>(min_deg) * kTenthsPerDegree;
  const std::int64_t max_tenths = static_cast<std::int64_t>(max_deg) * kTenthsPerDegree;
  if (min_tenths % step_tenths != 0 || max_tenths % step_tenths != 0) {
    fail("are not multiples of the grid step, " + grid_step_text(step_tenths) + " degrees");
  }
  const std::int64_t span = max_tenths - min_tenths;
  if (span < 0) fail("have min > max");
  // No wrap-around: min and max + one step must be distinct poses.
  if (span >= 360 * kTenthsPerDegree) fail("span 360 degrees or more");
  return static_cast<std::int32_t>(span / step_tenths + 1);
}

// Degrees of an angle in tenths: exact for multiples of 0.5 degree (and so
// bit-identical to the whole degrees of the 5-degree grid).
double degrees(std::int32_t tenths) {
  return static_cast<double>(tenths) / kTenthsPerDegree;
}

// Whether `deg` is a whole number of tenths of a degree (then in `tenths`).
bool whole_tenths(double deg, std::int64_t& tenths) {
  const double scaled = deg * kTenthsPerDegree;
  if (!std::isfinite(scaled) || std::abs(scaled) > 1e9) return false;
  tenths = std::llround(scaled);
  return static_cast<double>(tenths) == scaled;
}

std::string degrees_text(double deg) {
  std::int64_t tenths = 0;
  if (whole_tenths(deg, tenths)) {
    return (tenths < 0 ? "-" : "") +
           grid_step_text(static_cast<std::int32_t>(tenths < 0 ? -tenths : tenths));
  }
  return std::to_string(deg);
}

}  // namespace

std::string_view action_name(std::int32_t action) {
  Arm::check_action(action);
  return kActionNames[static_cast<std::size_t>(action)];
}

Arm::Arm(const ArmConfig& config) : config_(config) {
  check_geometry(config_.geometry);
  const JointLimits& limits = config_.limits;
  const std::int32_t step = config_.grid_step_tenths;
  if (step < 1) {
    throw ArmConfigError(
        ArmConfigField::grid_step, -1,
        "arm grid step " + std::to_string(step) + " tenths of a degree is not >= 1 (0.1 degree)");
  }
  shoulder_steps_ = grid_steps(limits.shoulder_min_deg, limits.shoulder_max_deg, step,
                               ArmConfigField::shoulder_limits, "shoulder");
  elbow_steps_ = grid_steps(limits.elbow_min_deg, limits.elbow_max_deg, step,
                            ArmConfigField::elbow_limits, "elbow");

  // The collision/goal grid, once: every later query is a table look-up.
  state_at_.assign(static_cast<std::size_t>(shoulder_steps_) * elbow_steps_, kNoState);
  for (std::int32_t i = 0; i < shoulder_steps_; ++i) {
    for (std::int32_t j = 0; j < elbow_steps_; ++j) {
      const ArmPose pose = forward_kinematics(config_.geometry, degrees(shoulder_tenths(i)),
                                              degrees(elbow_tenths(j)));
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
      "arm start A (" + degrees_text(a.shoulder_deg) + ", " + degrees_text(a.elbow_deg) + ")";
  const auto fail_start = [&](const std::string& why) {
    throw ArmConfigError(ArmConfigField::start_A, -1, shown + why);
  };
  std::int64_t shoulder_a = 0;
  std::int64_t elbow_a = 0;
  if (!whole_tenths(a.shoulder_deg, shoulder_a) || !whole_tenths(a.elbow_deg, elbow_a) ||
      shoulder_a % step != 0 || elbow_a % step != 0) {
    fail_start(" is not on the " + grid_step_text(step) + "-degree grid");
  }
  if (a.shoulder_deg < limits.shoulder_min_deg || a.shoulder_deg > limits.shoulder_max_deg ||
      a.elbow_deg < limits.elbow_min_deg || a.elbow_deg > limits.elbow_max_deg) {
    fail_start(" is outside the joint limits");
  }
  start_state_A_ = state_of(static_cast<std::int32_t>((shoulder_a - shoulder_tenths(0)) / step),
                            static_cast<std::int32_t>((elbow_a - elbow_tenths(0)) / step));
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

double Arm::grid_step_degrees() const {
  return degrees(config_.grid_step_tenths);
}

std::int32_t Arm::shoulder_tenths(std::int32_t i_shoulder) const {
  return config_.limits.shoulder_min_deg * kTenthsPerDegree + config_.grid_step_tenths * i_shoulder;
}

std::int32_t Arm::elbow_tenths(std::int32_t i_elbow) const {
  return config_.limits.elbow_min_deg * kTenthsPerDegree + config_.grid_step_tenths * i_elbow;
}

JointAngles Arm::angles_of(std::int32_t state) const {
  const GridCell cell = cell_of(state);
  return {degrees(shoulder_tenths(cell.shoulder)), degrees(elbow_tenths(cell.elbow))};
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
  // Tenths / 50 is the correctly rounded (shoulder_deg / 5): on the 5-degree grid
  // the very values of whole degrees / 5.
  constexpr double kTenthsPerUnit = static_cast<double>(kJointUnitDegrees) * kTenthsPerDegree;
  const GridCell cell = cell_of(state);
  return {static_cast<double>(shoulder_tenths(cell.shoulder)) / kTenthsPerUnit,
          static_cast<double>(elbow_tenths(cell.elbow)) / kTenthsPerUnit};
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
