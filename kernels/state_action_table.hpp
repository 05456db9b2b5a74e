#pragma once
// The feature table of one fit (state_action_basis.hpp's schemes) as the fit reads
// it: through an index into the state kernels where the table is made of their
// rows (shared_row_basis.hpp: the copy scheme, and the shift scheme of a
// deterministic model such as the arm's), else formed (a stochastic model's shift
// table). Either way fit, greedy and values give fit_lspi's, greedy_policy's and
// state_values's results on the formed table, bit for bit.
//
// Thread-safety: const members are reentrant.

#include <cstdint>
#include <optional>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/lspi.hpp"
#include "kernels/sample_batch.hpp"
#include "kernels/state_action_basis.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::kernels {

class StateActionTable {
 public:
  // model: the empirical model of the shift scheme (unused, may be null, for the
  // copy scheme). Keeps a reference to state_kernels. Throws std::invalid_argument
  // as copy_basis / shift_basis do.
  StateActionTable(const SparseRowMatrix& state_kernels, std::int32_t num_actions,
                   BasisScheme scheme, const EmpiricalTransitionModel* model);

  LspiResult fit(const SampleBatch& samples, const LspiOptions& options) const;
  std::vector<std::int32_t> greedy(const Eigen::VectorXd& weights) const;
  Eigen::VectorXd values(const Eigen::VectorXd& weights) const;

  // True when the table is read through the kernels' rows (not formed).
  bool shares_rows() const { return rows_.has_value(); }

 private:
  SparseRowMatrix compressed_storage_;  // the kernels compressed, where they were not
  const SparseRowMatrix& kernels_;
  std::int32_t num_actions_;
  std::optional<std::vector<std::int32_t>> rows_;
  SparseRowMatrix table_;  // formed where rows_ is empty
};

}  // namespace ggk::kernels
