#include "kernels/shared_row_basis.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "kernels/copy_basis_greedy.hpp"
#include "kernels/first_best.hpp"
#include "kernels/state_action_basis.hpp"

namespace ggk::kernels {

void check_shared_rows(const SparseRowMatrix& kernels, std::span<const std::int32_t> row_of_pair,
                       std::int32_t num_actions, const char* caller) {
  if (!kernels.isCompressed()) {
    throw std::invalid_argument(std::string(caller) + ": the kernels are not compressed");
  }
  if (num_actions <= 0 || row_of_pair.size() % static_cast<std::size_t>(num_actions) != 0) {
    throw std::invalid_argument(std::string(caller) + ": " + std::to_string(row_of_pair.size()) +
                                " pairs are not a whole number of states of " +
                                std::to_string(num_actions) + " actions");
  }
  for (std::size_t pair = 0; pair < row_of_pair.size(); ++pair) {
    const std::int32_t row = row_of_pair[pair];
    if (row < 0 || row >= kernels.rows()) {
      throw std::invalid_argument(std::string(caller) + ": pair " + std::to_string(pair) +
                                  " has row " + std::to_string(row) + ", outside the " +
                                  std::to_string(kernels.rows()) + " rows of its kernels");
    }
  }
}

namespace {

// Q(s, a) = values(row_of_pair[s m + a], a), handed to emit(s, q) state by state.
template <class Emit>
void for_each_state_q(const SparseRowMatrix& kernels, std::span<const std::int32_t> row_of_pair,
                      std::int32_t num_actions, const Eigen::VectorXd& weights, const Emit& emit) {
  check_shared_rows(kernels, row_of_pair, num_actions, "shared_row_basis");
  const RowMatrixXd values = copy_action_values(kernels, 1, kernels.cols(), num_actions, weights);
  const auto m = static_cast<std::size_t>(num_actions);
  std::vector<double> q(m);
  for (std::size_t s = 0; s < row_of_pair.size() / m; ++s) {
    for (std::size_t a = 0; a < m; ++a) {
      q[a] = values(row_of_pair[s * m + a], static_cast<Eigen::Index>(a));
    }
    emit(s, q.data());
  }
}

}  // namespace

std::vector<std::int32_t> copy_basis_rows(std::int32_t num_states, std::int32_t num_actions) {
  std::vector<std::int32_t> rows(static_cast<std::size_t>(num_states) *
                                 static_cast<std::size_t>(num_actions));
  for (std::size_t pair = 0; pair < rows.size(); ++pair) {
    rows[pair] = static_cast<std::int32_t>(pair / static_cast<std::size_t>(num_actions));
  }
  return rows;
}

std::optional<std::vector<std::int32_t>> shift_basis_rows(const SparseRowMatrix& state_kernels,
                                                          std::int32_t num_actions,
                                                          const EmpiricalTransitionModel& model) {
  if (num_actions <= 0 || model.num_states() != state_kernels.rows() ||
      model.num_actions() != num_actions) {
    shift_basis(state_kernels, num_actions, model);  // throws its own message
  }
  for (Eigen::Index row = 0; row < state_kernels.outerSize(); ++row) {
    for (SparseRowMatrix::InnerIterator it(state_kernels, row); it; ++it) {
      if (it.value() == 0.0 && std::signbit(it.value())) return std::nullopt;
    }
  }
  std::vector<std::int32_t> rows = copy_basis_rows(model.num_states(), num_actions);
  for (std::int32_t s = 0; s < model.num_states(); ++s) {
    for (std::int32_t a = 0; a < num_actions; ++a) {
      if (!model.observed(s, a)) continue;
      const auto successors = model.successors(s, a);
      if (successors.size() != 1 || model.probabilities(s, a)[0] != 1.0) return std::nullopt;
      rows[static_cast<std::size_t>(s) * static_cast<std::size_t>(num_actions) +
           static_cast<std::size_t>(a)] = successors[0];
    }
  }
  return rows;
}

SparseRowMatrix shared_row_table(const SparseRowMatrix& kernels,
                                 std::span<const std::int32_t> row_of_pair,
                                 std::int32_t num_actions) {
  check_shared_rows(kernels, row_of_pair, num_actions, "shared_row_table");
  const Eigen::Index p = kernels.cols();
  SparseRowMatrix table(static_cast<Eigen::Index>(row_of_pair.size()), p * num_actions);
  Eigen::Index nonzeros = 0;
  for (const std::int32_t row : row_of_pair) nonzeros += kernels.row(row).nonZeros();
  table.reserve(nonzeros);
  for (std::size_t pair = 0; pair < row_of_pair.size(); ++pair) {
    const auto row = static_cast<Eigen::Index>(pair);
    const Eigen::Index offset = (row % num_actions) * p;
    table.startVec(row);
    for (SparseRowMatrix::InnerIterator it(kernels, row_of_pair[pair]); it; ++it) {
      table.insertBack(row, offset + it.col()) = it.value();
    }
  }
  table.finalize();
  return table;
}

std::vector<std::int32_t> shared_row_greedy(const SparseRowMatrix& kernels,
                                            std::span<const std::int32_t> row_of_pair,
                                            std::int32_t num_actions,
                                            const Eigen::VectorXd& weights) {
  std::vector<std::int32_t> policy(row_of_pair.size() / static_cast<std::size_t>(num_actions));
  for_each_state_q(kernels, row_of_pair, num_actions, weights,
                   [&](std::size_t s, const double* q) { policy[s] = first_best(q, num_actions); });
  return policy;
}

Eigen::VectorXd shared_row_state_values(const SparseRowMatrix& kernels,
                                        std::span<const std::int32_t> row_of_pair,
                                        std::int32_t num_actions, const Eigen::VectorXd& weights) {
  Eigen::VectorXd values(static_cast<Eigen::Index>(row_of_pair.size()) / num_actions);
  for_each_state_q(kernels, row_of_pair, num_actions, weights, [&](std::size_t s, const double* q) {
    // As state_values: Eigen's maxCoeff over the m values.
    values(static_cast<Eigen::Index>(s)) =
        Eigen::Map<const Eigen::VectorXd>(q, num_actions).maxCoeff();
  });
  return values;
}

}  // namespace ggk::kernels
