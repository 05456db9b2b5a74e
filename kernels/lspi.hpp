#pragma once
// Least-squares policy iteration (Lagoudakis & Parr 2003; paper sec. 2.2) over a
// fixed batch of samples and a fixed feature table.
//
// Q(s, a) = w^T phi(s, a), Eq. (4), with phi(s, a) = features.row(s * m + a).
// Policy evaluation, for the current greedy policy pi (W = diag(sample weights),
// phi'_i = phi(s'_i, pi(s'_i)), zero when sample i is terminal):
//   BRM     psi_i = phi_i - gamma phi'_i;  (Psi^T W Psi + lambda I) w = Psi^T W r
//           (symmetric; Cholesky: CHOLMOD or LAPACK dpotrf)
//   LSTD-Q  (Phi^T W (Phi - gamma Phi') + lambda I) w = Phi^T W r
//           (LU: UMFPACK or LAPACK dgetrf; LinearAlgebra picks sparse or dense)
// The features must be in action-block form (action_block_system.hpp: phi(s, a)
// lives in columns [a p, (a + 1) p)), as the copy and shift schemes build them; A is
// formed block by block with dense BLAS products, then factorised densely or
// compressed for a sparse solver.
// Policy improvement, Eq. (6): pi(s) = argmax_a Q(s, a), ties to the lowest action.
// The first policy is the greedy policy of w = 0, i.e. action 0 everywhere.
// Iteration stops by one of two rules (LspiStopping), or after max_iterations
// evaluations:
//   policy_unchanged   the greedy action stopped changing on every sample state (a
//                      state some sample starts from or bootstraps from);
//   weights_converged  ||w_k - w_{k-1}||_2 <= weight_tolerance, w_0 = 0: the rule of
//                      Lagoudakis & Parr's LSPI code (lspi.m; its Python port
//                      lspi-python defaults epsilon to 1e-5).
// Both quantities are recorded for every iteration whichever rule stops it. The
// returned policy covers all table states.
//
// Thread-safety: fit_lspi is reentrant; distinct calls may run in parallel.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/sample_batch.hpp"
#include "kernels/sparse_solvers.hpp"

namespace ggk::kernels {

class ActionBlockFixed;  // action_block_system.hpp

enum class LspiSolver { brm, lstdq };

enum class LspiStopping { policy_unchanged, weights_converged };

// The ridge each evaluation adds to its system A (BRM: Psi^T W Psi; LSTD-Q:
// Phi^T W (Phi - gamma Phi'_pi)): absolute: lambda I (lambda = LspiOptions::ridge);
// relative: lambda s I with s = sum_j |A_jj| / k, the mean absolute diagonal entry
// of the k x k system before the ridge, formed anew in every evaluation. For BRM
// (A positive semi-definite) s = trace(A) / k: the mean eigenvalue of A, its
// nuclear norm over k, and ||W^1/2 Psi||_F^2 / k; lambda is then a share of A's
// scale, whatever the kernels' and the samples' numbers make that scale.
enum class RidgeScale { absolute, relative };

// How each evaluation's system is factorised. sparse: CHOLMOD (BRM) / UMFPACK
// (LSTD-Q) on the compressed system; dense: LAPACK dpotrf / dgetrf
// (dense_solvers.hpp), LU in block triangular form over the action blocks;
// automatic: dense when at least kDenseSystemDensity of the entries the solver
// reads (BRM: the lower triangle) are non-zero, else sparse, decided per
// evaluation. The kinds agree to rounding (different elimination orders), not bit
// for bit. Where the greedy step meets an exact tie they must agree exactly:
// - Weights that are zero in exact arithmetic (a block of actions that no reward
//   reaches through the system's block structure) stay exact zeros under
//   Cholesky, dense or sparse (no pivoting: products and sums of zeros), under
//   UMFPACK, and under the dense LU in block triangular form. A plain pivoted LU
//   of the whole matrix leaves rounding residue (~1e-13) there, and the argmax
//   over Q values that are 0 in exact arithmetic then follows the residue instead
//   of the lowest-action rule: with it, 8 of the 480 LSTD-Q fits of
//   jobs/maze.toml (run 10) changed policy. The same holds for A itself: its
//   structural zeros are exact after ActionBlockSystem::update's rank-r updates
//   as after a rebuild (an entry no sample reaches is reset, not left as the
//   residue of a subtraction: with that residue, 4 of the 96 fits of
//   jobs/ci.toml with sigma 2 and truncation 0.05 changed policy).
// - The density threshold is measured (bench/lspi_benchmark.cpp, BM_SolveSystem,
//   LSPI systems of truncated kernels at k = 400 and 1,600): dense Cholesky wins
//   from a density between 0.2 and 0.6 (CHOLMOD's supernodes stay competitive
//   longer at large k), dense LU from near 0.2.
enum class LinearAlgebra { automatic, sparse, dense };
inline constexpr double kDenseSystemDensity = 0.25;

struct LspiOptions {
  double gamma = 0.9;
  double ridge = 0.0;  // lambda
  RidgeScale ridge_scale = RidgeScale::absolute;
  std::int32_t max_iterations = 20;
  LspiSolver solver = LspiSolver::brm;
  LspiStopping stopping = LspiStopping::policy_unchanged;
  double weight_tolerance = 1e-5;  // epsilon of weights_converged
  bool keep_iterates = false;      // LspiResult::iterates holds every evaluation's weights
  LinearAlgebra linear_algebra = LinearAlgebra::automatic;
  SolverSettings solver_settings{};
};

enum class LspiStatus {
  converged,       // the stopping rule held
  max_iterations,  // still changing after max_iterations evaluations
  solver_failed,   // an evaluation system was singular or ill-conditioned
};

const char* to_string(LspiStatus status);
const char* to_string(LspiSolver solver);
const char* to_string(LspiStopping stopping);  // "policy" or "weights"
const char* to_string(LinearAlgebra kind);     // "auto", "sparse" or "dense"
const char* to_string(RidgeScale scale);       // "absolute" or "relative"

struct LspiIteration {
  std::int32_t policy_changes =
      0;                       // sample states whose greedy action changed after this evaluation
  double weight_change = 0.0;  // ||w_k - w_{k-1}||_2, w_0 = 0
  double relative_residual = 0.0;
  double rcond = 0.0;
  bool reused_analysis = false;
  bool dense_solve = false;  // factorised by LAPACK (dense), not CHOLMOD / UMFPACK
};

struct LspiResult {
  LspiStatus status = LspiStatus::max_iterations;
  std::string message;                    // the solver's reason when status is solver_failed
  Eigen::VectorXd weights;                // of the last successful evaluation; size 0 if none
  std::vector<std::int32_t> policy;       // greedy action per table state for `weights`
  std::vector<LspiIteration> history;     // one entry per successful evaluation
  std::vector<Eigen::VectorXd> iterates;  // with keep_iterates: w_1 .. w_k, else empty
  SparseColMatrix a;  // system of the last successful evaluation (BRM: lower triangle only)
  Eigen::VectorXd b;

  std::int32_t iterations() const { return static_cast<std::int32_t>(history.size()); }
  bool ok() const { return status != LspiStatus::solver_failed; }
};

// features: (N m) x k in action-block form; samples index states in [0, N). Throws
// std::invalid_argument on inconsistent shapes or samples, or other features.
LspiResult fit_lspi(const SparseRowMatrix& features, std::int32_t num_actions,
                    const SampleBatch& samples, const LspiOptions& options);

// fit_lspi(copy_basis(state_kernels, num_actions), num_actions, samples, options)
// from the state kernels (N x p) alone, bit for bit the same result, without the
// (N m) x (m p) table (m times the kernels' memory) or the pass that builds it.
// `shared`: the system's fixed part for these same kernels and samples
// (ActionBlockSystem::copy_basis_fixed), formed once for fits that differ only in
// their solver or gamma (the same result bit for bit); null: formed here.
LspiResult fit_lspi_copy_basis(const SparseRowMatrix& state_kernels, std::int32_t num_actions,
                               const SampleBatch& samples, const LspiOptions& options,
                               std::shared_ptr<const ActionBlockFixed> shared = nullptr);

// fit_lspi_copy_basis for states that share their kernels: state s has row
// row_of_state[s] of `row_kernels` (e.g. the Khepera's readings and the SOM unit
// whose proto-value functions they take). The result equals fit_lspi_copy_basis on
// the expanded kernels (row s = row_kernels.row(row_of_state[s])) bit for bit,
// policy per state and policy_changes counting states included: the system sums the
// same terms in the same order, and each greedy step reads every distinct row once
// instead of once per state. Every row must belong to some state (else
// std::invalid_argument, as for rows out of range).
LspiResult fit_lspi_copy_basis(const SparseRowMatrix& row_kernels,
                               std::span<const std::int32_t> row_of_state, std::int32_t num_actions,
                               const SampleBatch& samples, const LspiOptions& options);

// fit_lspi_copy_basis(row_kernels, row_of_state, ...) with the system summed over
// the distinct (row, action) and (action, successor row) pairs of the samples
// instead of the samples (pooled_copy_samples.hpp): the same A and b in exact
// arithmetic, up to rounding in floating point (the sums run in another order).
// It pays where many states share a row: the Khepera's 20,000 readings on ~700
// SOM units sum ~2,700 and ~2,600 pairs. The greedy step, the policy per state
// and the policy changes are as in fit_lspi_copy_basis; a fit whose policies
// oscillate can settle on another policy where the rounding breaks a near tie.
LspiResult fit_lspi_pooled_copy_basis(const SparseRowMatrix& row_kernels,
                                      std::span<const std::int32_t> row_of_state,
                                      std::int32_t num_actions, const SampleBatch& samples,
                                      const LspiOptions& options);

// fit_lspi(shared_row_table(kernels, row_of_pair, num_actions), num_actions,
// samples, options) from the kernels and the index alone (shared_row_basis.hpp:
// the copy scheme, and the shift scheme of a deterministic model), bit for bit the
// same result, without the table or the pass that builds it; the system gathers
// and the greedy step reads R p kernel values instead of N m p table values.
// std::invalid_argument on rows outside the kernels, a row_of_pair that is not a
// whole number of states, or samples outside its N states.
LspiResult fit_lspi_shared_rows(const SparseRowMatrix& kernels,
                                std::span<const std::int32_t> row_of_pair, std::int32_t num_actions,
                                const SampleBatch& samples, const LspiOptions& options);

// Q(s, a) for every table row, i.e. features * w.
Eigen::VectorXd action_values(const SparseRowMatrix& features, const Eigen::VectorXd& weights);

// argmax_a Q(s, a) per state (ties to the lowest action).
std::vector<std::int32_t> greedy_policy(const SparseRowMatrix& features, std::int32_t num_actions,
                                        const Eigen::VectorXd& weights);

// True when `features` is a copy-basis table: for every state the rows of all
// actions hold the same entries, those of action a shifted by a p columns.
bool is_copy_layout(const SparseRowMatrix& features, std::int32_t num_actions);

// greedy_policy for a copy-basis table (is_copy_layout), reading only the rows of
// action 0 (a quarter of the table for 4 actions): Q(s, a) sums the same products
// in the same order as features * w, so the policy is bit for bit greedy_policy's.
// fit_lspi uses it when the table is a copy basis.
std::vector<std::int32_t> copy_layout_greedy_policy(const SparseRowMatrix& features,
                                                    std::int32_t num_actions,
                                                    const Eigen::VectorXd& weights);

// V(s) = max_a Q(s, a) per state.
Eigen::VectorXd state_values(const SparseRowMatrix& features, std::int32_t num_actions,
                             const Eigen::VectorXd& weights);

}  // namespace ggk::kernels
