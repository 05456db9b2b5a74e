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
// Policy iteration changes the bootstrap action b_i of only some samples, so
// `update` keeps C, E and b of the last policy and moves just those samples from
// group (a_i, b_old) to (a_i, b_new): a rank-r update costing ~6 r p^2 flops (BRM)
// instead of ~3 n p^2. It rebuilds everything instead when 2 r >= n_live (the
// non-terminal samples) or on the first call; a rebuild gives A and b bit for bit
// as `assemble` (but for the copy basis's rebuilds after the first, below). An
// updated A equals the rebuilt one up to rounding (the sums run in another order:
// differences of a few ulps of the summed magnitudes). Exact zeros stay exact: an
// entry of C, E or b that no sample of its group reaches with a non-zero term
// (truncated kernels, unreachable centres, zero rewards) is exactly zero in
// `assemble`, and a subtraction would leave rounding residue there instead (~1e-15
// of the removed terms), which breaks the greedy step's exact ties (lspi.hpp). So
// `update` also keeps, per entry, how many samples of its group contribute a
// non-zero term (exact integers, from the same products on 0/1 indicators), and
// resets every entry whose count falls to zero. The counts of C and E are kept
// only when some feature row has a zero (a table without any makes every count its
// group's size: an emptied group, reset whole); they double the flops of an update
// and of update's rebuilds.
//
// The copy basis read from its state kernels (CopyBasisTag, or shared rows that
// are the same for every action) has bootstrap vectors that do not depend on the
// bootstrap action: v_i = sqrt(w_i) kappa(s'_i) whatever b_i, which only picks the
// block. So sum_y C_xy (per x) and sum_y E_y are fixed by the samples, and a
// rebuild after the first one forms every block but the largest group's
// directly and that one by subtraction: C_xy* = sum_y C_xy - sum_{y != y*} C_xy,
// y* the bootstrap action most of x's samples take, and E likewise (y* over all
// samples). The Khepera's readings take "forward" 75-89 % of the time, so its PVF
// BRM fits, whose policies oscillate and rebuild most iterations, skip most of
// their products. The sums are formed from the first rebuild's blocks (bit for bit
// as today, so fits that never rebuild again are unchanged); a subtracted block
// differs from the directly summed one by rounding of the totals' magnitude (a few
// ulps of sum_y |C_xy|: tests/kernels/action_block_system_test.cpp bounds it), and
// its counts, exact integers, by subtraction too, reset the entries no sample of
// the group reaches to exact zeros as `update` does. The right-hand side is always
// summed directly (n p flops). last_update_subtracted() says when a rebuild did
// this.
//
// Thread-safety: const members may be called from several threads; `update`
// changes the object (one thread at a time).

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/lspi.hpp"
#include "kernels/sample_batch.hpp"

namespace ggk::kernels {

// Empty when `features` is in action-block form for num_actions, else a sentence
// naming the first row that is not (for an error message).
std::string action_block_violation(const SparseRowMatrix& features, std::int32_t num_actions);

// What the system keeps that no policy, solver or gamma changes: the samples'
// weights' roots, D_a, the start right-hand side sum_i e_{a_i} u_i sqrt(w_i) r_i
// and what the table holds (zeros, underflow). Formed once per table and samples
// (~n p^2 flops and a pass over the table) and shared by the systems of fits that
// differ only in their solver or gamma: each gives A and b bit for bit as when it
// forms its own. Keeps references to the table and the samples. Defined in
// action_block_system.cpp.
class ActionBlockFixed;

class ActionBlockSystem {
 public:
  // features must be in action-block form and samples valid for the table (both
  // checked by fit_lspi). Keeps references to features and samples.
  ActionBlockSystem(const SparseRowMatrix& features, std::int32_t num_actions,
                    const SampleBatch& samples, LspiSolver solver, double gamma);

  // The copy basis given by its state kernels alone (N x p, kappa(s, a) = row s for
  // every a): the same A and b bit for bit as for the table copy_basis(state_kernels,
  // num_actions), without forming it. Keeps references to state_kernels and samples.
  struct CopyBasisTag {};
  static constexpr CopyBasisTag copy_basis_tag{};
  // `shared`: the fixed part made by copy_basis_fixed for this same state_kernels,
  // num_actions and samples (the same objects, else std::invalid_argument), or
  // null to form it here.
  ActionBlockSystem(CopyBasisTag, const SparseRowMatrix& state_kernels, std::int32_t num_actions,
                    const SampleBatch& samples, LspiSolver solver, double gamma,
                    std::shared_ptr<const ActionBlockFixed> shared = nullptr);
  // The table whose row s m + a is row row_of_pair[s m + a] of `kernels` (R x p) in
  // block a (shared_row_basis.hpp): the same A and b bit for bit as for
  // shared_row_table(kernels, row_of_pair, num_actions), without forming it. Keeps
  // references to kernels, row_of_pair and samples (rows and samples checked by
  // fit_lspi_shared_rows).
  struct SharedRowsTag {};
  static constexpr SharedRowsTag shared_rows_tag{};
  ActionBlockSystem(SharedRowsTag, const SparseRowMatrix& kernels,
                    std::span<const std::int32_t> row_of_pair, std::int32_t num_actions,
                    const SampleBatch& samples, LspiSolver solver, double gamma);
  // The copy basis's fixed part, to share between systems. std::invalid_argument
  // unless state_kernels is compressed and the samples valid for its rows.
  // start_samples (rows of state_kernels too; kept only while this returns): the
  // samples D_a and the start right-hand side are formed from instead of `samples`,
  // which then give only C, E and the bootstrap part of b: pooled samples
  // (pooled_copy_samples.hpp), whose start vectors are not those of D.
  static std::shared_ptr<const ActionBlockFixed> copy_basis_fixed(
      const SparseRowMatrix& state_kernels, std::int32_t num_actions, const SampleBatch& samples,
      const SampleBatch* start_samples = nullptr);

  // A (k x k, dense; BRM: symmetric, both triangles) and b for the greedy policy
  // `policy` (an action per table state).
  void assemble(const std::vector<std::int32_t>& policy, Eigen::MatrixXd& a,
                Eigen::VectorXd& b) const;

  // As assemble, but from the blocks of the previous call's policy by a rank-r
  // update where fewer than half of the live samples changed bootstrap action.
  // Returns the number of samples updated (0 and a rebuild are told apart by
  // last_update_rebuilt()).
  std::int64_t update(const std::vector<std::int32_t>& policy, Eigen::MatrixXd& a,
                      Eigen::VectorXd& b);
  bool last_update_rebuilt() const { return last_rebuilt_; }
  // The last update was a rebuild with its largest groups' blocks by subtraction.
  bool last_update_subtracted() const { return last_subtracted_; }

  // p: A is m x m blocks of this size, one per action pair.
  Eigen::Index block_size() const { return p_; }

 private:
  // The policy-dependent parts: C_xy (m * m blocks, row x * m + y), E_y (m blocks,
  // lower triangle, BRM), b (start_rhs_ minus gamma sum_i e_{b_i} v_i sqrt(w_i) r_i
  // for BRM), and the size of every (x, y) group. With `supports`, the number of
  // the group's samples with a non-zero term in each entry: cross_support and
  // next_support beside cross and next (when the table has zeros), rhs_support
  // beside the policy-dependent sum in rhs (BRM); empty when not kept.
  struct PolicyBlocks {
    std::vector<Eigen::MatrixXd> cross;
    std::vector<Eigen::MatrixXd> next;
    Eigen::VectorXd rhs;
    std::vector<std::int64_t> group_sizes;
    std::vector<Eigen::MatrixXd> cross_support;
    std::vector<Eigen::MatrixXd> next_support;
    Eigen::VectorXd rhs_support;
  };

  // The sums over the bootstrap actions of a system whose bootstrap vectors do not
  // depend on them (bootstrap_free_): cross[x] = sum_y C_xy, next = sum_y E_y
  // (lower triangle), and their counts where the blocks keep counts. Empty until the
  // first rebuild forms them.
  struct GroupTotals {
    std::vector<Eigen::MatrixXd> cross;
    Eigen::MatrixXd next;
    std::vector<Eigen::MatrixXd> cross_support;
    Eigen::MatrixXd next_support;
  };

  // The blocks a rebuild by subtraction derives instead of summing: C_{x, cross[x]}
  // and E_next (-1: none).
  struct DerivedBlocks {
    std::vector<std::int32_t> cross;
    std::int32_t next = -1;
  };

  // Buffers of the gathered rows, reused from group to group and call to call (a
  // fresh matrix per group costs page faults and a zero fill of new pages).
  struct Scratch {
    std::vector<double> u, v, rewards;
    std::vector<double> u_support, v_support, reward_support;  // 0/1 indicators
  };

  // supports: keep the counts of non-zero terms (update's blocks; assemble's need
  // none).
  void reset(PolicyBlocks& blocks, bool supports) const;
  // Adds (sign +1) or removes (sign -1) the samples `groups[x * m + y]` (each in
  // sample order) with bootstrap action y to / from the blocks; a removal resets
  // the entries no remaining sample reaches (where the blocks keep counts).
  // `derived`: the blocks to leave out (a rebuild by subtraction), or null.
  void accumulate(const std::vector<std::vector<std::int32_t>>& groups, double sign,
                  PolicyBlocks& blocks, Scratch& scratch,
                  const DerivedBlocks* derived = nullptr) const;
  // The totals from the blocks of a rebuild.
  GroupTotals group_totals(const PolicyBlocks& blocks) const;
  // The largest group of each x (C) and over all x (E), ties to the lowest action.
  DerivedBlocks largest_groups(const std::vector<std::vector<std::int32_t>>& groups) const;
  // Forms the `derived` blocks of `blocks` (whose other blocks are summed) by
  // subtraction from totals_, their counts likewise, resetting the entries that no
  // sample of the group reaches.
  void subtract_from_totals(const DerivedBlocks& derived, PolicyBlocks& blocks) const;
  void compose(const PolicyBlocks& blocks, Eigen::MatrixXd& a, Eigen::VectorXd& b) const;
  // Non-terminal samples grouped by (a_i, b_i), each group in sample order.
  std::vector<std::vector<std::int32_t>> full_groups(const std::vector<std::int32_t>& policy) const;

  // The fixed part's: sqrt(w_i) kappa of the samples `rows` (start or successor
  // states), and sqrt(w_i) r_i (ActionBlockFixed in action_block_system.cpp).
  Eigen::Map<Eigen::MatrixXd> gather(const std::vector<std::int32_t>& rows, bool next_state,
                                     std::int32_t action, std::vector<double>& buffer) const;
  Eigen::Map<Eigen::VectorXd> weighted_rewards(const std::vector<std::int32_t>& rows,
                                               std::vector<double>& buffer) const;

  ActionBlockSystem(std::shared_ptr<const ActionBlockFixed> fixed, LspiSolver solver, double gamma);

  std::shared_ptr<const ActionBlockFixed> fixed_;
  // Of *fixed_, by their names before it was shared.
  const SparseRowMatrix& features_;  // the table, or the state kernels (copy_rows_)
  bool copy_rows_;  // features_ holds state kernels: kappa(s, a) is a row of it, in columns 0 .. p
  const SampleBatch& samples_;
  std::int32_t num_actions_;
  Eigen::Index p_;
  Eigen::Index k_;  // m p
  LspiSolver solver_;
  double gamma_;
  const std::vector<Eigen::MatrixXd>& start_blocks_;  // D_a, both triangles
  const Eigen::VectorXd& start_rhs_;                  // sum_i e_{a_i} u_i sqrt(w_i) r_i
  std::int64_t live_samples_;                         // non-terminal samples
  bool table_has_zeros_;  // some row of features_ has fewer than p non-zeros
  // No gathered entry sqrt(w_i) kappa is zero (no zero in the table, no underflow):
  // the BRM right-hand side's counts need no indicator products.
  bool gathered_without_zeros_;
  // State of `update`: the blocks and every sample's bootstrap action for the last
  // policy (-1 for terminal samples); empty before the first call.
  PolicyBlocks cached_;
  std::vector<std::int32_t> bootstrap_;
  bool last_rebuilt_ = false;
  bool last_subtracted_ = false;
  bool bootstrap_free_;  // v_i does not depend on b_i (the copy basis from its kernels)
  GroupTotals totals_;
  Scratch scratch_;  // of `update`
};

}  // namespace ggk::kernels
