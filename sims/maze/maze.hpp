#pragma once
// Grid maze (Sugiyama et al., the task on which geodesic Gaussian kernels were
// first evaluated): an ASCII map of walls '#', free cells '.' and goal cells 'G'.
//
// States are the non-wall cells, numbered 0..n-1 in row-major order; the state
// vector of a state is its (row, col) as doubles, so Euclidean distances between
// states are distances between cell centres. Four actions move one cell up, down,
// left or right; a move into a wall or off the grid leaves the agent in place.
// Entering a goal cell gives reward +1 and ends the episode.
//
// Thread-safety: immutable after construction; step() draws only from the stream
// it is given, so distinct streams may step one Maze in parallel.

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::sims::maze {

inline constexpr std::int32_t kUp = 0;     // row - 1
inline constexpr std::int32_t kDown = 1;   // row + 1
inline constexpr std::int32_t kLeft = 2;   // col - 1
inline constexpr std::int32_t kRight = 3;  // col + 1
inline constexpr std::int32_t kNumActions = 4;

// "up", "down", "left", "right"; throws std::out_of_range for other values.
std::string_view action_name(std::int32_t action);

// state_of() for a wall or a cell off the grid.
inline constexpr std::int32_t kNoState = -1;

struct Cell {
  std::int32_t row = 0;
  std::int32_t col = 0;
  friend bool operator==(const Cell&, const Cell&) = default;
};

struct StepResult {
  std::int32_t next_state = 0;
  double reward = 0.0;    // +1 on entering a goal from a non-goal state, else 0
  bool terminal = false;  // next_state is a goal
};

// A map that cannot be parsed. row() and column() are 1-based and count lines and
// characters of the text as given (so they match a map file's lines); both are 0
// when the error has no position (no free cell, no goal).
class MazeParseError : public std::invalid_argument {
 public:
  MazeParseError(std::int32_t row, std::int32_t column, const std::string& reason);
  std::int32_t row() const { return row_; }
  std::int32_t column() const { return column_; }
  const std::string& reason() const { return reason_; }

 private:
  std::int32_t row_;
  std::int32_t column_;
  std::string reason_;
};

class Maze {
 public:
  // Parses ASCII art: rows separated by '\n' ("\r\n" accepted); leading and
  // trailing blank lines and trailing whitespace of each row are ignored. Throws
  // MazeParseError on ragged rows, characters other than '#', '.', 'G', a map
  // without a free cell '.' or without a goal 'G'.
  explicit Maze(std::string_view text);

  std::int32_t rows() const { return rows_; }
  std::int32_t cols() const { return cols_; }
  std::int32_t num_states() const { return static_cast<std::int32_t>(cells_.size()); }
  std::int32_t num_actions() const { return kNumActions; }

  // The state at (row, col), or kNoState for a wall or a cell off the grid.
  std::int32_t state_of(std::int32_t row, std::int32_t col) const;
  // Throws std::out_of_range for a state outside [0, num_states()).
  Cell cell_of(std::int32_t state) const;
  bool is_goal(std::int32_t state) const;
  // Goal states in increasing order.
  const std::vector<std::int32_t>& goal_states() const { return goal_states_; }

  // (row, col) of a state as doubles.
  std::array<double, 2> state_vector(std::int32_t state) const;
  // num_states() x 2, row s = state_vector(s).
  kernels::RowMatrixXd state_vectors() const;

  // The state reached by moving in `action`'s direction, without slip.
  std::int32_t move(std::int32_t state, std::int32_t action) const;

  // One transition. With probability `slip` the agent moves in one of the three
  // other directions, chosen uniformly; slip must lie in [0, 1]. With slip == 0 no
  // random number is drawn. Throws std::out_of_range for a bad state or action and
  // std::invalid_argument for a bad slip.
  StepResult step(std::int32_t state, std::int32_t action, kernels::RandomStream& random,
                  double slip) const;

  // Throws std::out_of_range unless 0 <= action < kNumActions.
  static void check_action(std::int32_t action);

  // The map as text, one '\n'-terminated line per row (walls, free cells, goals).
  std::string to_text() const;

 private:
  void check_state(std::int32_t state) const;

  std::int32_t rows_ = 0;
  std::int32_t cols_ = 0;
  std::vector<std::int32_t> state_at_;  // rows_ * cols_, kNoState for walls
  std::vector<Cell> cells_;             // per state
  std::vector<std::uint8_t> goal_;      // per state
  std::vector<std::int32_t> goal_states_;
};

}  // namespace ggk::sims::maze
