#pragma once
// The policy-evaluation system of LSPI (lspi.hpp) for features in action-block
// form: phi(s, a) is zero outside columns [a p, (a + 1) p), p = k / m, as both
// schemes of state_action_basis.hpp build it. Row s * m + a of the table holds
// kappa(s, a), a p-vector, in block a.
//
// With u_i = sqrt(w_i) kappa(s_i, a_i), v_i = sqrt(w_i) kappa(s'_i, b_i),
// b_i = pi(s'_i), and e_a the indicator of block a (v_i = 0 for terminal samples):
//   BRM     A = sum_i (e_{a_i} u_i - gamma e_{b_i} v_i)(e_{a_i} u_i - gamma e_{b_i} v_i)^T
//   LSTD-Q  A = sum_i  e_{a_i} u_i (e_{a_i} u_i - gamma e_{b_i} v_i)^T
// so every p x p block of A is a dense product over the samples of one action pair:
//   D_a  = sum_{a_i = a} u_i u_i^T                (fixed; formed once)
//   C_ab = sum_{a_i = a, b_i = b} u_i v_i^T       (per policy)
//   E_b  = sum_{b_i = b} v_i v_i^T                (per policy; BRM only)
// BRM: A = diag(D) - gamma (C + C^T) + gamma^2 diag(E); LSTD-Q: A = diag(D) - gamma C.
// The products run as BLAS GEMM / SYRK (EIGEN_USE_BLAS, serial OpenBLAS) on the
// samples gathered per (a_i, b_i) group in sample order, so A is deterministic.
// Cost per policy: ~3 n p^2 flops (2 n p^2 for LSTD-Q) and O(k^2 + n p) memory.
//
// Thread-safety: const members may be called from several threads.

#include <cstdint>
#include <string>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/lspi.hpp"
#include "kernels/sample_batch.hpp"

namespace ggk::kernels {

// Empty when `features` is in action-block form for num_actions, else a sentence
// naming the first row that is not (for an error message).
std::string action_block_violation(const SparseRowMatrix& features, std::int32_t num_actions);

class ActionBlockSystem {
 public:
  // features must be in action-block form and samples valid for the table (both
  // checked by fit_lspi). Keeps references to features and samples.
  ActionBlockSystem(const SparseRowMatrix& features, std::int32_t num_actions,
                    const SampleBatch& samples, LspiSolver solver, double gamma);

  // A (k x k, dense; BRM: symmetric, both triangles) and b for the greedy policy
  // `policy` (an action per table state).
  void assemble(const std::vector<std::int32_t>& policy, Eigen::MatrixXd& a,
                Eigen::VectorXd& b) const;

 private:
  // Row r of the result is sqrt(w_i) kappa(s, action) for sample i = rows[r], s its
  // start (next_state = false) or successor state.
  Eigen::MatrixXd gather(const std::vector<std::int32_t>& rows, bool next_state,
                         std::int32_t action) const;

  // sqrt(w_i) r_i for sample i = rows[r].
  Eigen::VectorXd weighted_rewards(const std::vector<std::int32_t>& rows) const;

  const SparseRowMatrix& features_;
  const SampleBatch& samples_;
  std::int32_t num_actions_;
  Eigen::Index p_;
  LspiSolver solver_;
  double gamma_;
  std::vector<double> sqrt_weights_;
  std::vector<Eigen::MatrixXd> start_blocks_;  // D_a, both triangles
  Eigen::VectorXd start_rhs_;                  // sum_i e_{a_i} u_i sqrt(w_i) r_i
};

}  // namespace ggk::kernels
