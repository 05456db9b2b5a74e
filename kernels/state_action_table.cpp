#include "kernels/state_action_table.hpp"

#include <stdexcept>
#include <string>

#include "kernels/shared_row_basis.hpp"

namespace ggk::kernels {

namespace {

SparseRowMatrix compressed_copy(const SparseRowMatrix& kernels) {
  if (kernels.isCompressed()) return {};
  SparseRowMatrix copy = kernels;
  copy.makeCompressed();
  return copy;
}

}  // namespace

StateActionTable::StateActionTable(const SparseRowMatrix& state_kernels, std::int32_t num_actions,
                                   BasisScheme scheme, const EmpiricalTransitionModel* model)
    : compressed_storage_(compressed_copy(state_kernels)),
      kernels_(state_kernels.isCompressed() ? state_kernels : compressed_storage_),
      num_actions_(num_actions) {
  if (num_actions <= 0) {
    throw std::invalid_argument("StateActionTable: num_actions must be > 0, got " +
                                std::to_string(num_actions));
  }
  if (scheme == BasisScheme::copy) {
    rows_ = copy_basis_rows(static_cast<std::int32_t>(kernels_.rows()), num_actions);
    return;
  }
  if (model == nullptr) {
    throw std::invalid_argument("StateActionTable: the shift scheme needs a transition model");
  }
  rows_ = shift_basis_rows(kernels_, num_actions, *model);
  if (!rows_) table_ = shift_basis(kernels_, num_actions, *model);
}

LspiResult StateActionTable::fit(const SampleBatch& samples, const LspiOptions& options) const {
  if (rows_) return fit_lspi_shared_rows(kernels_, *rows_, num_actions_, samples, options);
  return fit_lspi(table_, num_actions_, samples, options);
}

std::vector<std::int32_t> StateActionTable::greedy(const Eigen::VectorXd& weights) const {
  if (rows_) return shared_row_greedy(kernels_, *rows_, num_actions_, weights);
  return greedy_policy(table_, num_actions_, weights);
}

Eigen::VectorXd StateActionTable::values(const Eigen::VectorXd& weights) const {
  if (rows_) return shared_row_state_values(kernels_, *rows_, num_actions_, weights);
  return state_values(table_, num_actions_, weights);
}

}  // namespace ggk::kernels
