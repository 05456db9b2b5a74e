#pragma once
// The arm MDP on the joint grid (paper sec. 4.1, Fig. 1(b)).
//
// The shoulder and elbow angles take the values of JointLimits on a grid of
// ArmConfig::grid_step_tenths (5 degrees by default, the paper's: 37 x 72 cells;
// 2.5 degrees: 73 x 143), without wrap-around. A grid cell is a state when the
// arm in that pose meets no obstacle; states are numbered 0..n-1 row-major over
// the grid (shoulder index major, elbow index minor). A state is a goal when the
// end effector touches the object.
//
// State vector: (shoulder_deg, elbow_deg) / 5 (kJointUnitDegrees), whatever the
// grid step: at the default step neighbouring states are at Euclidean distance 1,
// at 2.5 degrees at 0.5 (the edge weight of the sample graph and the metric of
// ordinary Gaussian kernels), so a kernel width means the same angle at any step.
//
// Four actions turn one joint by +-1 grid step. A move into a colliding pose or
// past a limit leaves the arm where it is. Entering a goal gives reward +1 and
// ends the episode; every other transition gives 0. Transitions are deterministic.
//
// Thread-safety: the collision/goal grid is computed once in the constructor;
// afterwards every member is const and an Arm may be shared by any number of
// threads.

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "sims/arm/arm_config.hpp"
#include "sims/arm/arm_config_error.hpp"
#include "sims/arm/kinematics.hpp"

namespace ggk::sims::arm {

inline constexpr std::int32_t kShoulderPlus = 0;   // shoulder + 1 grid step
inline constexpr std::int32_t kShoulderMinus = 1;  // shoulder - 1 grid step
inline constexpr std::int32_t kElbowPlus = 2;      // elbow + 1 grid step
inline constexpr std::int32_t kElbowMinus = 3;     // elbow - 1 grid step
inline constexpr std::int32_t kNumActions = 4;

// "shoulder+", "shoulder-", "elbow+", "elbow-"; throws std::out_of_range otherwise.
std::string_view action_name(std::int32_t action);

// state_of() for a colliding cell or one off the grid.
inline constexpr std::int32_t kNoState = -1;

// Grid indices: angle = limit min + grid step * index.
struct GridCell {
  std::int32_t shoulder = 0;
  std::int32_t elbow = 0;
  friend bool operator==(const GridCell&, const GridCell&) = default;
};

struct StepResult {
  std::int32_t next_state = 0;
  double reward = 0.0;    // +1 on entering a goal from a non-goal state, else 0
  bool terminal = false;  // next_state is a goal
};

class Arm {
 public:
  // Throws ArmConfigError (a std::invalid_argument naming the field at fault) for
  // a bad geometry (check_geometry), a grid step < 1 tenth of a degree, limits
  // that are not multiples of the step, a grid without a free cell or without a
  // goal, or a start_A that is off the grid, collides or is a goal.
  explicit Arm(const ArmConfig& config);

  const ArmConfig& config() const { return config_; }
  std::int32_t shoulder_steps() const { return shoulder_steps_; }  // grid rows (37 at 5 degrees)
  std::int32_t elbow_steps() const { return elbow_steps_; }        // grid columns (72 at 5 degrees)
  std::int32_t grid_step_tenths() const { return config_.grid_step_tenths; }
  double grid_step_degrees() const;
  std::int32_t num_states() const { return static_cast<std::int32_t>(cells_.size()); }
  std::int32_t num_actions() const { return kNumActions; }

  // The state of a grid cell, or kNoState for a colliding cell or one off the grid.
  std::int32_t state_of(std::int32_t i_shoulder, std::int32_t i_elbow) const;
  // Whether the arm collides in a grid cell; throws std::out_of_range off the grid.
  bool collides(std::int32_t i_shoulder, std::int32_t i_elbow) const;
  // Throws std::out_of_range for a state outside [0, num_states()).
  GridCell cell_of(std::int32_t state) const;
  JointAngles angles_of(std::int32_t state) const;  // degrees, min + step * index
  ArmPose pose_of(std::int32_t state) const;
  bool is_goal(std::int32_t state) const;
  // Goal states in increasing order.
  const std::vector<std::int32_t>& goal_states() const { return goal_states_; }
  // The configured start pose 'A' as a state (a free non-goal state).
  std::int32_t start_state_A() const { return start_state_A_; }

  // (shoulder_deg, elbow_deg) / 5 of a state (kJointUnitDegrees), at any grid step.
  std::array<double, 2> state_vector(std::int32_t state) const;
  // num_states() x 2, row s = state_vector(s).
  kernels::RowMatrixXd state_vectors() const;

  // The state reached by `action` (the same state when the move is blocked).
  std::int32_t move(std::int32_t state, std::int32_t action) const;
  // One deterministic transition. Throws std::out_of_range for a bad state or action.
  StepResult step(std::int32_t state, std::int32_t action) const;

  // Throws std::out_of_range unless 0 <= action < kNumActions.
  static void check_action(std::int32_t action);

 private:
  void check_state(std::int32_t state) const;
  // The angles of a cell in tenths of a degree (exact integers).
  std::int32_t shoulder_tenths(std::int32_t i_shoulder) const;
  std::int32_t elbow_tenths(std::int32_t i_elbow) const;

  ArmConfig config_;
  std::int32_t shoulder_steps_ = 0;
  std::int32_t elbow_steps_ = 0;
  std::vector<std::int32_t> state_at_;  // shoulder_steps_ * elbow_steps_, kNoState if colliding
  std::vector<GridCell> cells_;         // per state
  std::vector<std::uint8_t> goal_;      // per state
  std::vector<std::int32_t> goal_states_;
  std::int32_t start_state_A_ = kNoState;
};

}  // namespace ggk::sims::arm
