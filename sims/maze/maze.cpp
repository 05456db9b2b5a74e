#include "sims/maze/maze.hpp"

#include <algorithm>
#include <cstddef>
#include <string>

namespace ggk::sims::maze {
namespace {

constexpr std::array<std::string_view, kNumActions> kActionNames = {"up", "down", "left", "right"};
constexpr std::array<std::int32_t, kNumActions> kRowDelta = {-1, 1, 0, 0};
constexpr std::array<std::int32_t, kNumActions> kColDelta = {0, 0, -1, 1};

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

std::string_view trim_trailing_blanks(std::string_view line) {
  while (!line.empty() && is_blank(line.back())) line.remove_suffix(1);
  return line;
}

std::string position_message(std::int32_t row, std::int32_t column, const std::string& reason) {
  if (row == 0) return "invalid maze: " + reason;
  return "invalid maze at row " + std::to_string(row) + ", column " + std::to_string(column) +
         ": " + reason;
}

std::string describe_char(char c) {
  if (c == ' ') return "' ' (space)";
  if (c == '\t') return "'\\t' (tab)";
  const auto u = static_cast<unsigned char>(c);
  if (u < 0x20 || u >= 0x7f) return "byte " + std::to_string(u);
  return std::string("'") + c + "'";
}

}  // namespace

std::string_view action_name(std::int32_t action) {
  Maze::check_action(action);
  return kActionNames[static_cast<std::size_t>(action)];
}

MazeParseError::MazeParseError(std::int32_t row, std::int32_t column, const std::string& reason)
    : std::invalid_argument(position_message(row, column, reason)),
      row_(row),
      column_(column),
      reason_(reason) {}

Maze::Maze(std::string_view text) {
  // Split into lines, remembering each line's 1-based number in the text so that
  // errors point at the line a user sees in the map file.
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = text.find('\n', start);
    const std::size_t stop = end == std::string_view::npos ? text.size() : end;
    lines.push_back(trim_trailing_blanks(text.substr(start, stop - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  std::size_t first = 0;
  std::size_t last = lines.size();
  while (first < last && lines[first].empty()) ++first;
  while (last > first && lines[last - 1].empty()) --last;
  if (first == last) throw MazeParseError(0, 0, "the map is empty");

  rows_ = static_cast<std::int32_t>(last - first);
  cols_ = static_cast<std::int32_t>(lines[first].size());
  state_at_.assign(static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_), kNoState);
  bool has_free_cell = false;
  for (std::int32_t r = 0; r < rows_; ++r) {
    const std::size_t line_index = first + static_cast<std::size_t>(r);
    const std::string_view line = lines[line_index];
    const auto text_row = static_cast<std::int32_t>(line_index + 1);
    if (static_cast<std::int32_t>(line.size()) != cols_) {
      // Point at the first character past the shorter of the two widths.
      const auto width = static_cast<std::int32_t>(line.size());
      throw MazeParseError(text_row, std::min(width, cols_) + 1,
                           "row has " + std::to_string(width) + " cells, the first row has " +
                               std::to_string(cols_) + " (rows must have equal width)");
    }
    for (std::int32_t c = 0; c < cols_; ++c) {
      const char symbol = line[static_cast<std::size_t>(c)];
      if (symbol == '#') continue;
      if (symbol != '.' && symbol != 'G') {
        throw MazeParseError(text_row, c + 1,
                             "unknown character " + describe_char(symbol) +
                                 " (expected '#' wall, '.' free or 'G' goal)");
      }
      const auto state = static_cast<std::int32_t>(cells_.size());
      state_at_[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols_) +
                static_cast<std::size_t>(c)] = state;
      cells_.push_back({r, c});
      goal_.push_back(symbol == 'G' ? 1 : 0);
      if (symbol == 'G') goal_states_.push_back(state);
      has_free_cell = has_free_cell || symbol == '.';
    }
  }
  if (!has_free_cell) throw MazeParseError(0, 0, "the map has no free cell '.'");
  if (goal_states_.empty()) throw MazeParseError(0, 0, "the map has no goal cell 'G'");
}

std::int32_t Maze::state_of(std::int32_t row, std::int32_t col) const {
  if (row < 0 || row >= rows_ || col < 0 || col >= cols_) return kNoState;
  return state_at_[static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) +
                   static_cast<std::size_t>(col)];
}

void Maze::check_state(std::int32_t state) const {
  if (state < 0 || state >= num_states()) {
    throw std::out_of_range("maze state " + std::to_string(state) + " is not in [0, " +
                            std::to_string(num_states()) + ")");
  }
}

void Maze::check_action(std::int32_t action) {
  if (action < 0 || action >= kNumActions) {
    throw std::out_of_range("maze action " + std::to_string(action) + " is not in [0, " +
                            std::to_string(kNumActions) + ")");
  }
}

Cell Maze::cell_of(std::int32_t state) const {
  check_state(state);
  return cells_[static_cast<std::size_t>(state)];
}

bool Maze::is_goal(std::int32_t state) const {
  check_state(state);
  return goal_[static_cast<std::size_t>(state)] != 0;
}

std::array<double, 2> Maze::state_vector(std::int32_t state) const {
  const Cell cell = cell_of(state);
  return {static_cast<double>(cell.row), static_cast<double>(cell.col)};
}

kernels::RowMatrixXd Maze::state_vectors() const {
  kernels::RowMatrixXd vectors(num_states(), 2);
  for (std::int32_t s = 0; s < num_states(); ++s) {
    const Cell& cell = cells_[static_cast<std::size_t>(s)];
    vectors(s, 0) = static_cast<double>(cell.row);
    vectors(s, 1) = static_cast<double>(cell.col);
  }
  return vectors;
}

std::int32_t Maze::move(std::int32_t state, std::int32_t action) const {
  const Cell cell = cell_of(state);
  check_action(action);
  const auto a = static_cast<std::size_t>(action);
  const std::int32_t next = state_of(cell.row + kRowDelta[a], cell.col + kColDelta[a]);
  return next == kNoState ? state : next;
}

StepResult Maze::step(std::int32_t state, std::int32_t action, kernels::RandomStream& random,
                      double slip) const {
  if (!(slip >= 0.0 && slip <= 1.0)) {
    throw std::invalid_argument("maze slip " + std::to_string(slip) + " is not in [0, 1]");
  }
  check_state(state);
  check_action(action);
  std::int32_t actual = action;
  if (slip > 0.0 && random.bernoulli(slip)) {
    // One of the three other directions, uniformly: skip over the intended one.
    const auto other = static_cast<std::int32_t>(random.uniform_index(kNumActions - 1));
    actual = other < action ? other : other + 1;
  }
  StepResult result;
  result.next_state = move(state, actual);
  result.terminal = is_goal(result.next_state);
  result.reward = result.terminal && !is_goal(state) ? 1.0 : 0.0;
  return result;
}

std::string Maze::to_text() const {
  std::string text;
  text.reserve(static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_ + 1));
  for (std::int32_t r = 0; r < rows_; ++r) {
    for (std::int32_t c = 0; c < cols_; ++c) {
      const std::int32_t s = state_of(r, c);
      text.push_back(s == kNoState ? '#' : (goal_[static_cast<std::size_t>(s)] != 0 ? 'G' : '.'));
    }
    text.push_back('\n');
  }
  return text;
}

}  // namespace ggk::sims::maze
