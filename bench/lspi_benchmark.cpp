// One LSPI fit with 6,400 distinct weighted samples: a 40 x 40 grid world (1,600
// states x 4 actions, one deterministic successor per pair, weights
// 1 + (31 s + 17 a) mod 40 so that bench/numpy_lspi_peer.py builds the same
// problem), p geodesic Gaussian centres (sigma 5), shift basis, goal in one corner.
// Cases: k = 400 (p = 100) with kernels truncated at 1e-3, as the foundations issue
// asks, and k = 800 (p = 200) untruncated, the arm's largest fit.
// Also times the feature construction on its own.

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/grid_graphs.hpp"
#include "kernels/action_block_greedy.hpp"
#include "kernels/action_block_system.hpp"
#include "kernels/avx2_dispatch.hpp"
#include "kernels/blas_runtime.hpp"
#include "kernels/copy_basis_greedy.hpp"
#include "kernels/dense_solvers.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/lspi.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/shared_row_basis.hpp"
#include "kernels/shortest_paths.hpp"
#include "kernels/state_action_basis.hpp"

namespace ggk::bench {
namespace {

constexpr std::int32_t kSide = 40;
constexpr std::int32_t kActions = 4;
constexpr double kSigma = 5.0;

struct GridProblem {
  kernels::SampleBatch samples;
  kernels::CsrGraph graph;
  std::vector<std::int32_t> centers;
};

GridProblem make_problem(std::int32_t num_centers) {
  GridProblem problem;
  problem.graph = grid_graph(kSide, kSide);
  const std::int32_t goal = kSide * kSide - 1;
  for (std::int32_t s = 0; s < kSide * kSide; ++s) {
    const std::int32_t r = s / kSide, c = s % kSide;
    for (std::int32_t a = 0; a < kActions; ++a) {
      const std::int32_t nr = std::clamp(r + (a == 0 ? -1 : a == 1 ? 1 : 0), 0, kSide - 1);
      const std::int32_t nc = std::clamp(c + (a == 2 ? -1 : a == 3 ? 1 : 0), 0, kSide - 1);
      const std::int32_t next = nr * kSide + nc;
      const bool terminal = next == goal && s != goal;
      problem.samples.add(s, a, terminal ? 1.0 : 0.0, next, terminal,
                          static_cast<double>(1 + (31 * s + 17 * a) % 40));
    }
  }
  problem.centers = spread_sources(problem.graph.num_nodes, num_centers);
  return problem;
}

kernels::SparseRowMatrix make_features(const GridProblem& problem, double truncation,
                                       double sigma = kSigma) {
  const kernels::RowMatrixXd distances =
      kernels::geodesic_distances(problem.graph, problem.centers);
  const kernels::SparseRowMatrix state_kernels =
      kernels::geodesic_gaussian_kernels(distances, sigma, truncation);
  const kernels::EmpiricalTransitionModel model(
      problem.graph.num_nodes, kActions, problem.samples.states, problem.samples.actions,
      problem.samples.next_states, problem.samples.weights);
  return kernels::shift_basis(state_kernels, kActions, model);
}

void BM_BuildFeatures(benchmark::State& state) {
  const GridProblem problem = make_problem(100);
  for (auto _ : state) {
    kernels::SparseRowMatrix features = make_features(problem, 1e-3);
    benchmark::DoNotOptimize(features.valuePtr());
  }
}
BENCHMARK(BM_BuildFeatures)->Unit(benchmark::kMillisecond)->UseRealTime();

// Named solver:brm / solver:lstdq; args: centres p (k = 4 p), truncation x 1e6.
void BM_FitLspi(benchmark::State& state, kernels::LspiSolver solver,
                kernels::LinearAlgebra linear_algebra) {
  const GridProblem problem = make_problem(static_cast<std::int32_t>(state.range(0)));
  const kernels::SparseRowMatrix features =
      make_features(problem, static_cast<double>(state.range(1)) * 1e-6);
  kernels::LspiOptions options;
  options.solver = solver;
  options.ridge = 1e-6;
  options.linear_algebra = linear_algebra;
  std::int64_t iterations = 0;
  for (auto _ : state) {
    const kernels::LspiResult result =
        kernels::fit_lspi(features, kActions, problem.samples, options);
    if (!result.ok()) state.SkipWithError(result.message.c_str());
    iterations = result.iterations();
    benchmark::DoNotOptimize(result.weights.data());
  }
  state.counters["lspi_iterations"] = static_cast<double>(iterations);
  state.counters["feature_nnz/row"] =
      static_cast<double>(features.nonZeros()) / static_cast<double>(features.rows());
  state.SetLabel(std::string(kernels::to_string(solver)) + " " +
                 kernels::to_string(linear_algebra));
}

// One BRM or LSTD-Q system of the grid problem for a random policy, kernels
// truncated at 1e-3, solved by each kind of linear algebra (the measurement behind
// LinearAlgebra::automatic's density threshold, lspi.hpp). Named
// solver:{brm,lstdq}/linear_algebra:{sparse,dense}; args: centres p, sigma x 10.
// Counter density: the share of non-zeros among the entries the solver reads.
void BM_SolveSystem(benchmark::State& state, kernels::LspiSolver solver,
                    kernels::LinearAlgebra kind) {
  const GridProblem problem = make_problem(static_cast<std::int32_t>(state.range(0)));
  const kernels::SparseRowMatrix features =
      make_features(problem, 1e-3, static_cast<double>(state.range(1)) / 10.0);
  kernels::RandomStream rng(11, 0, 0);
  std::vector<std::int32_t> policy(static_cast<std::size_t>(kSide * kSide));
  for (std::int32_t& action : policy) {
    action = static_cast<std::int32_t>(rng.uniform_index(kActions));
  }
  const bool brm = solver == kernels::LspiSolver::brm;
  const kernels::ActionBlockSystem system(features, kActions, problem.samples, solver, 0.9);
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  system.assemble(policy, a, b);
  const double ridge = 1e-6;
  Eigen::MatrixXd with_ridge = a;
  with_ridge.diagonal().array() += ridge;
  kernels::SparseColMatrix compressed =
      brm ? kernels::SparseColMatrix(
                with_ridge.triangularView<Eigen::Lower>().toDenseMatrix().sparseView())
          : kernels::SparseColMatrix(with_ridge.sparseView());
  compressed.makeCompressed();
  const double read = brm ? static_cast<double>(a.rows()) * static_cast<double>(a.rows() + 1) / 2
                          : static_cast<double>(a.size());
  kernels::SymmetricSolver symmetric;
  kernels::NonsymmetricSolver nonsymmetric;
  kernels::DenseSymmetricSolver dense_symmetric;
  kernels::DenseLuSolver dense_lu;
  Eigen::VectorXd x;
  for (auto _ : state) {
    kernels::SolveReport report;
    if (kind == kernels::LinearAlgebra::dense) {
      report = brm ? dense_symmetric.solve(a, ridge, b, x) : dense_lu.solve(a, ridge, b, x);
    } else {
      report = brm ? symmetric.solve(compressed, b, x) : nonsymmetric.solve(compressed, b, x);
    }
    if (!report.ok) state.SkipWithError(report.message.c_str());
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["density"] = static_cast<double>(compressed.nonZeros()) / read;
  state.counters["k"] = static_cast<double>(a.rows());
}

// Method: action blocks (ActionBlockSystem) or the Eigen sparse-product peer.
enum class AssembleMethod { action_blocks, eigen_sparse_product };

// One BRM system A = Psi^T W Psi for a fixed policy, two ways: ActionBlockSystem
// (dense p x p blocks through BLAS, what fit_lspi uses) and the peer, Eigen's
// sparse-sparse product of the rows psi_i = sqrt(w_i) (phi(s_i, a_i) - gamma
// phi(s'_i, pi(s'_i))) built from the feature table.
// Named method:action_blocks / method:eigen_sparse_product; args: centres p,
// truncation x 1e6.
void BM_AssembleBrmSystem(benchmark::State& state, AssembleMethod method) {
  const GridProblem problem = make_problem(static_cast<std::int32_t>(state.range(0)));
  const kernels::SparseRowMatrix features =
      make_features(problem, static_cast<double>(state.range(1)) * 1e-6);
  const kernels::SampleBatch& samples = problem.samples;
  kernels::RandomStream rng(11, 0, 0);
  std::vector<std::int32_t> policy(static_cast<std::size_t>(kSide * kSide));
  for (std::int32_t& action : policy) {
    action = static_cast<std::int32_t>(rng.uniform_index(kActions));
  }
  const double gamma = 0.9;
  if (method == AssembleMethod::action_blocks) {
    const kernels::ActionBlockSystem system(features, kActions, samples, kernels::LspiSolver::brm,
                                            gamma);
    Eigen::MatrixXd a;
    Eigen::VectorXd b;
    for (auto _ : state) {
      system.assemble(policy, a, b);
      benchmark::DoNotOptimize(a.data());
    }
    state.SetLabel("action blocks (BLAS)");
    return;
  }
  for (auto _ : state) {
    std::vector<Eigen::Triplet<double>> entries;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const double scale = std::sqrt(samples.weights[i]);
      const auto row = static_cast<Eigen::Index>(i);
      const std::int64_t start = std::int64_t{samples.states[i]} * kActions + samples.actions[i];
      for (kernels::SparseRowMatrix::InnerIterator it(features, start); it; ++it) {
        entries.emplace_back(row, it.col(), scale * it.value());
      }
      if (samples.terminals[i]) continue;
      const std::int32_t next = samples.next_states[i];
      const std::int64_t bootstrap =
          std::int64_t{next} * kActions + policy[static_cast<std::size_t>(next)];
      for (kernels::SparseRowMatrix::InnerIterator it(features, bootstrap); it; ++it) {
        entries.emplace_back(row, it.col(), -gamma * scale * it.value());
      }
    }
    kernels::SparseRowMatrix psi(static_cast<Eigen::Index>(samples.size()), features.cols());
    psi.setFromTriplets(entries.begin(), entries.end());
    const kernels::SparseColMatrix a = (psi.transpose() * psi).pruned();
    benchmark::DoNotOptimize(a.valuePtr());
  }
  state.SetLabel("Eigen sparse product");
}
// The shift basis (Eq. 9) of a deterministic task, as the arm's fits build it:
// the 40 x 40 grid world above (one successor per pair), p untruncated geodesic
// Gaussian centres (dense rows, k = 4 p).
void BM_ShiftBasis(benchmark::State& state) {
  const auto p = static_cast<std::int32_t>(state.range(0));
  const GridProblem problem = make_problem(p);
  const kernels::RowMatrixXd distances =
      kernels::geodesic_distances(problem.graph, problem.centers);
  const kernels::SparseRowMatrix state_kernels =
      kernels::geodesic_gaussian_kernels(distances, kSigma, 0.0);
  const kernels::EmpiricalTransitionModel model(
      problem.graph.num_nodes, kActions, problem.samples.states, problem.samples.actions,
      problem.samples.next_states, problem.samples.weights);
  for (auto _ : state) {
    kernels::SparseRowMatrix features = kernels::shift_basis(state_kernels, kActions, model);
    benchmark::DoNotOptimize(features.valuePtr());
  }
}
BENCHMARK(BM_ShiftBasis)
    ->ArgName("p")
    ->Arg(32)
    ->Arg(128)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The greedy step over that shift table (p = 128, k = 512, the arm's largest),
// method:{sparse_product,action_block,shared_rows}: greedy_policy (features * w,
// then the argmax) against action_block_greedy (kernels/action_block_greedy.hpp:
// the same policy bit for bit, the actions of a dense state summed side by side)
// and shared_row_greedy (kernels/shared_row_basis.hpp: the kernels' 1,600 rows read
// once for every action, Q looked up through the successors; the same policy).
enum class GreedyMethod { sparse_product, action_block, shared_rows };

void BM_ActionBlockGreedy(benchmark::State& state, GreedyMethod method) {
  constexpr std::int32_t kP = 128;
  const GridProblem problem = make_problem(kP);
  const kernels::RowMatrixXd distances =
      kernels::geodesic_distances(problem.graph, problem.centers);
  const kernels::EmpiricalTransitionModel model(
      problem.graph.num_nodes, kActions, problem.samples.states, problem.samples.actions,
      problem.samples.next_states, problem.samples.weights);
  const kernels::SparseRowMatrix state_kernels =
      kernels::geodesic_gaussian_kernels(distances, kSigma, 0.0);
  const kernels::SparseRowMatrix features = kernels::shift_basis(state_kernels, kActions, model);
  const std::vector<std::int32_t> rows = *kernels::shift_basis_rows(state_kernels, kActions, model);
  kernels::RandomStream rng(23, 0, 0);
  Eigen::VectorXd weights(features.cols());
  for (Eigen::Index e = 0; e < weights.size(); ++e) weights(e) = rng.uniform(-1, 1);
  for (auto _ : state) {
    const std::vector<std::int32_t> policy =
        method == GreedyMethod::action_block
            ? kernels::action_block_greedy(features, kActions, weights)
        : method == GreedyMethod::shared_rows
            ? kernels::shared_row_greedy(state_kernels, rows, kActions, weights)
            : kernels::greedy_policy(features, kActions, weights);
    benchmark::DoNotOptimize(policy.data());
  }
}

// A deterministic task's whole fit, as the arm's GGK fits run it (BRM, untruncated
// kernels, p centres, the grid problem above): method:table forms the shift table
// and fits it (fit_lspi, the path before shared rows), method:shared_rows fits
// through the kernels' rows (fit_lspi_shared_rows, kernels/shared_row_basis.hpp):
// the same fit bit for bit.
void BM_DeterministicShiftFit(benchmark::State& state, bool shared_rows) {
  const auto p = static_cast<std::int32_t>(state.range(0));
  const GridProblem problem = make_problem(p);
  const kernels::RowMatrixXd distances =
      kernels::geodesic_distances(problem.graph, problem.centers);
  const kernels::SparseRowMatrix state_kernels =
      kernels::geodesic_gaussian_kernels(distances, kSigma, 0.0);
  const kernels::EmpiricalTransitionModel model(
      problem.graph.num_nodes, kActions, problem.samples.states, problem.samples.actions,
      problem.samples.next_states, problem.samples.weights);
  kernels::LspiOptions options;
  options.ridge = 1e-6;
  std::int64_t iterations = 0;
  for (auto _ : state) {
    kernels::LspiResult result;
    if (shared_rows) {
      const std::vector<std::int32_t> rows =
          *kernels::shift_basis_rows(state_kernels, kActions, model);
      result =
          kernels::fit_lspi_shared_rows(state_kernels, rows, kActions, problem.samples, options);
    } else {
      result = kernels::fit_lspi(kernels::shift_basis(state_kernels, kActions, model), kActions,
                                 problem.samples, options);
    }
    if (!result.ok()) state.SkipWithError(result.message.c_str());
    iterations = result.iterations();
    benchmark::DoNotOptimize(result.weights.data());
  }
  state.counters["lspi_iterations"] = static_cast<double>(iterations);
}

// The greedy step of a copy basis over a Khepera-sized state-kernel table (20,200
// readings, 4 actions), each instruction path (kernels/copy_basis_greedy.hpp): named
// instructions:{portable,automatic} (automatic: AVX2 where the CPU has it, the
// label says which ran); args p and the share of non-zeros per row in percent (100:
// dense rows, as untruncated kernels and proto-value functions give).
void BM_CopyBasisGreedy(benchmark::State& state, kernels::GreedyInstructions instructions) {
  const auto p = static_cast<Eigen::Index>(state.range(0));
  const double kept = static_cast<double>(state.range(1)) / 100.0;
  constexpr Eigen::Index kStates = 20200;
  kernels::RandomStream rng(13, 0, 0);
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index s = 0; s < kStates; ++s) {
    for (Eigen::Index j = 0; j < p; ++j) {
      if (kept < 1.0 && rng.uniform() >= kept) continue;
      entries.emplace_back(s, j, rng.uniform());
    }
  }
  kernels::SparseRowMatrix table(kStates, p);
  table.setFromTriplets(entries.begin(), entries.end());
  table.makeCompressed();
  Eigen::VectorXd weights(p * kActions);
  for (Eigen::Index e = 0; e < weights.size(); ++e) weights(e) = rng.uniform() - 0.5;
  for (auto _ : state) {
    const std::vector<std::int32_t> policy =
        kernels::copy_greedy(table, 1, p, kActions, weights, instructions);
    benchmark::DoNotOptimize(policy.data());
  }
  state.counters["MB_values"] = static_cast<double>(table.nonZeros()) * 8.0 / 1e6;
  state.SetLabel(instructions == kernels::GreedyInstructions::automatic && kernels::cpu_has_avx2()
                     ? "avx2"
                     : "portable");
}

// The Khepera's shapes for the system benchmarks below: a dense copy table of
// kReadings readings x p random kernel values, and kSamples samples (reading i to
// i + 1, random actions and rewards), drawn from rng in that order.
constexpr std::int32_t kReadings = 20200, kSamples = 20000;

struct KheperaShapes {
  kernels::SparseRowMatrix table;
  kernels::SampleBatch samples;
};

KheperaShapes khepera_shapes(Eigen::Index p, kernels::RandomStream& rng) {
  KheperaShapes shapes;
  kernels::RowMatrixXd dense(kReadings, p);
  for (Eigen::Index e = 0; e < dense.size(); ++e) dense.data()[e] = rng.uniform(-1, 1);
  shapes.table = dense.sparseView();
  shapes.table.makeCompressed();
  for (std::int32_t i = 0; i < kSamples; ++i) {
    shapes.samples.add(i, static_cast<std::int32_t>(rng.uniform_index(kActions)), rng.uniform(),
                       i + 1, false);
  }
  return shapes;
}

// The limit of the dominant kernel (bench/README.md, "Limits"): one full BRM
// rebuild (ActionBlockSystem::assemble, what every iteration of a Khepera PVF BRM
// fit does) at the Khepera's shapes: 20,000 samples over 20,200 readings, 4
// actions, a dense copy table of p columns, a random policy. Counter GFlops:
// 3 n p^2 flops (C blocks 2 n p^2 by GEMM, E blocks n p^2 by SYRK) per second.
void BM_BrmRebuild(benchmark::State& state) {
  const auto p = static_cast<Eigen::Index>(state.range(0));
  kernels::RandomStream rng(17, 0, 0);
  const KheperaShapes shapes = khepera_shapes(p, rng);
  const kernels::SparseRowMatrix& table = shapes.table;
  const kernels::SampleBatch& samples = shapes.samples;
  std::vector<std::int32_t> policy(kReadings);
  for (std::int32_t& action : policy) {
    action = static_cast<std::int32_t>(rng.uniform_index(kActions));
  }
  const kernels::ActionBlockSystem system(kernels::ActionBlockSystem::copy_basis_tag, table,
                                          kActions, samples, kernels::LspiSolver::brm, 0.9);
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  for (auto _ : state) {
    system.assemble(policy, a, b);
    benchmark::DoNotOptimize(a.data());
  }
  state.counters["GFlops"] = benchmark::Counter(3.0 * kSamples * static_cast<double>(p * p) / 1e9,
                                                benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BrmRebuild)
    ->ArgName("p")
    ->Arg(10)
    ->Arg(50)
    ->Arg(100)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// A BRM rebuild after the first, as the Khepera's PVF fits make most iterations
// (their policies oscillate), at BM_BrmRebuild's shapes with the bootstrap actions
// of the Khepera (80 % one action: 0 in one policy, 1 in the other; the two
// alternate and differ in most samples, so every update rebuilds): method:direct
// sums every group (ActionBlockSystem::assemble, what every rebuild did before),
// method:subtraction is update's rebuild (the largest groups' blocks by
// subtraction from the sums over the bootstrap actions). Counter GFlops: 3 n p^2
// flops (the direct rebuild's) per second.
void BM_BrmRebuildAfterTheFirst(benchmark::State& state, bool subtraction) {
  const auto p = static_cast<Eigen::Index>(state.range(0));
  kernels::RandomStream rng(17, 0, 0);
  const KheperaShapes shapes = khepera_shapes(p, rng);
  const kernels::SparseRowMatrix& table = shapes.table;
  const kernels::SampleBatch& samples = shapes.samples;
  std::vector<std::int32_t> policies[2];
  for (std::int32_t k = 0; k < 2; ++k) {
    policies[k].resize(kReadings);
    for (std::int32_t& action : policies[k]) {
      action = rng.uniform() < 0.8 ? k : static_cast<std::int32_t>(rng.uniform_index(kActions));
    }
  }
  kernels::ActionBlockSystem system(kernels::ActionBlockSystem::copy_basis_tag, table, kActions,
                                    samples, kernels::LspiSolver::brm, 0.9);
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  system.update(policies[1], a, b);  // the first rebuild: the sums
  std::size_t next = 0;
  for (auto _ : state) {
    if (subtraction) {
      system.update(policies[next], a, b);
      if (!system.last_update_subtracted()) state.SkipWithError("the update did not subtract");
    } else {
      system.assemble(policies[next], a, b);
    }
    next = 1 - next;
    benchmark::DoNotOptimize(a.data());
  }
  state.counters["GFlops"] = benchmark::Counter(3.0 * kSamples * static_cast<double>(p * p) / 1e9,
                                                benchmark::Counter::kIsIterationInvariantRate);
}

// The Khepera's PVF fits (issue 38, session 25): 20,000 readings on 690 SOM units
// (a reading's unit and its successor's close on a ring, as a robot's are), 4
// actions, a dense PVF-like row of p values per unit, one BRM fit of at most 20
// iterations. method:shared_rows sums the system over the readings
// (fit_lspi_copy_basis with row_of_state, the old path), method:pooled over the
// distinct (unit, action) and (action, successor unit) pairs
// (fit_lspi_pooled_copy_basis). Counter iterations: the fit's.
void BM_UnitRowsFit(benchmark::State& state, bool pooled) {
  const auto p = static_cast<Eigen::Index>(state.range(0));
  constexpr std::int32_t kUnits = 690;
  kernels::RandomStream rng(23, 0, 0);
  kernels::RowMatrixXd dense(kUnits, p);
  for (Eigen::Index e = 0; e < dense.size(); ++e) dense.data()[e] = rng.uniform(-1, 1);
  kernels::SparseRowMatrix rows = dense.sparseView();
  rows.makeCompressed();
  std::vector<std::int32_t> row_of_state(kReadings);
  for (std::int32_t s = 0; s < kReadings; ++s) {
    row_of_state[static_cast<std::size_t>(s)] =
        s < kUnits ? s : static_cast<std::int32_t>(rng.uniform_index(kUnits));
  }
  kernels::SampleBatch samples;
  for (std::int32_t i = 0; i < kSamples; ++i) {
    const std::int32_t action = static_cast<std::int32_t>(rng.uniform_index(kActions));
    // The successor: a reading on a unit near this one's (the ring's next few).
    const std::int32_t unit = row_of_state[static_cast<std::size_t>(i)];
    const std::int32_t next_unit =
        (unit + static_cast<std::int32_t>(rng.uniform_index(4)) + action) % kUnits;
    samples.add(i, action, next_unit % 7 == 0 ? 1.0 : 0.0, next_unit, false);
  }
  kernels::LspiOptions options;
  options.solver = kernels::LspiSolver::brm;
  options.ridge = 1e-6;
  std::int32_t iterations = 0;
  for (auto _ : state) {
    const kernels::LspiResult fit =
        pooled ? kernels::fit_lspi_pooled_copy_basis(rows, row_of_state, kActions, samples, options)
               : kernels::fit_lspi_copy_basis(rows, row_of_state, kActions, samples, options);
    iterations = fit.iterations();
    benchmark::DoNotOptimize(fit.weights.data());
  }
  state.counters["iterations"] = iterations;
}

// The OGK tables of one Khepera run (issue 38, session 25): 20,200 readings of 8
// sensors, centres from them, kernel counts 10, 20, ..., 100, width 1000.
// method:each builds every count's table (the old path, 550 columns of exp),
// method:prefix the largest and the others as its leading columns
// (kernels::leading_columns, bit for bit the same tables).
void BM_KernelTablesOverCounts(benchmark::State& state, bool prefix) {
  kernels::RandomStream rng(29, 0, 0);
  kernels::RowMatrixXd readings(kReadings, 8);
  for (Eigen::Index e = 0; e < readings.size(); ++e) readings.data()[e] = rng.uniform(0, 1023);
  const kernels::RowMatrixXd centers = readings.topRows(100);
  for (auto _ : state) {
    std::vector<kernels::SparseRowMatrix> tables;
    if (prefix) {
      const kernels::SparseRowMatrix largest =
          kernels::ordinary_gaussian_kernels(readings, centers, 1000.0);
      for (Eigen::Index p = 10; p <= 100; p += 10) {
        tables.push_back(kernels::leading_columns(largest, p));
      }
    } else {
      for (Eigen::Index p = 10; p <= 100; p += 10) {
        tables.push_back(kernels::ordinary_gaussian_kernels(readings, centers.topRows(p), 1000.0));
      }
    }
    benchmark::DoNotOptimize(tables.data());
  }
}

// The systems of a BRM and an LSTD-Q fit of one table (what the Khepera's two
// solvers at one kernel count build before their first iteration), at the
// Khepera's shapes as BM_BrmRebuild (p = 100): shared:0 forms the fixed part (D_a
// and the start right-hand side: the table's scans, the gather and n p^2 flops of
// SYRK) in each system, shared:1 once for both (ActionBlockSystem::copy_basis_fixed,
// as engine/tasks/khepera/khepera_task.cpp's fit_points does).
void BM_SolverPairFixedPart(benchmark::State& state) {
  const bool shared = state.range(0) != 0;
  constexpr Eigen::Index kP = 100;
  kernels::RandomStream rng(19, 0, 0);
  const KheperaShapes shapes = khepera_shapes(kP, rng);
  const kernels::SparseRowMatrix& table = shapes.table;
  const kernels::SampleBatch& samples = shapes.samples;
  for (auto _ : state) {
    const auto fixed =
        shared ? kernels::ActionBlockSystem::copy_basis_fixed(table, kActions, samples) : nullptr;
    const kernels::ActionBlockSystem brm(kernels::ActionBlockSystem::copy_basis_tag, table,
                                         kActions, samples, kernels::LspiSolver::brm, 0.9, fixed);
    const kernels::ActionBlockSystem lstdq(kernels::ActionBlockSystem::copy_basis_tag, table,
                                           kActions, samples, kernels::LspiSolver::lstdq, 0.9,
                                           fixed);
    benchmark::DoNotOptimize(&brm);
    benchmark::DoNotOptimize(&lstdq);
  }
}
BENCHMARK(BM_SolverPairFixedPart)
    ->ArgName("shared")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The machine's dense peak through the same BLAS and thread setting: one 1,024 x
// 1,024 GEMM (2 n^3 flops), counter GFlops.
void BM_DgemmPeak(benchmark::State& state) {
  constexpr Eigen::Index kSize = 1024;
  kernels::use_calling_thread_blas();
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(kSize, kSize);
  const Eigen::MatrixXd y = Eigen::MatrixXd::Random(kSize, kSize);
  Eigen::MatrixXd z(kSize, kSize);
  for (auto _ : state) {
    z.noalias() = x * y;
    benchmark::DoNotOptimize(z.data());
  }
  state.counters["GFlops"] = benchmark::Counter(2.0 * kSize * kSize * kSize / 1e9,
                                                benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_DgemmPeak)->Unit(benchmark::kMillisecond)->UseRealTime();

// Registered with named values (solver:brm, not solver:0): the case
// k = 400 with truncated kernels, and the arm's largest, k = 800 untruncated.
const bool kRegistered = [] {
  const std::pair<const char*, kernels::LspiSolver> solvers[] = {
      {"brm", kernels::LspiSolver::brm}, {"lstdq", kernels::LspiSolver::lstdq}};
  for (const auto& [name, solver] : solvers) {
    for (const kernels::LinearAlgebra kind :
         {kernels::LinearAlgebra::sparse, kernels::LinearAlgebra::dense}) {
      const std::string values =
          std::string("/solver:") + name + "/linear_algebra:" + kernels::to_string(kind);
      benchmark::RegisterBenchmark(("BM_FitLspi" + values).c_str(), BM_FitLspi, solver, kind)
          ->ArgNames({"p", "truncation_e6"})
          ->Args({100, 1000})
          ->Args({200, 0})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("BM_SolveSystem" + values).c_str(), BM_SolveSystem, solver,
                                   kind)
          ->ArgNames({"p", "sigma_x10"})
          ->ArgsProduct({{100, 400}, {10, 20, 40, 80}})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  const std::pair<const char*, kernels::GreedyInstructions> paths[] = {
      {"portable", kernels::GreedyInstructions::portable},
      {"automatic", kernels::GreedyInstructions::automatic}};
  for (const auto& [name, instructions] : paths) {
    benchmark::RegisterBenchmark((std::string("BM_CopyBasisGreedy/instructions:") + name).c_str(),
                                 BM_CopyBasisGreedy, instructions)
        ->ArgNames({"p", "nonzero_percent"})
        ->Args({100, 100})
        ->Args({50, 100})
        ->Args({100, 30})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  const std::pair<const char*, GreedyMethod> greedy_methods[] = {
      {"sparse_product", GreedyMethod::sparse_product},
      {"action_block", GreedyMethod::action_block},
      {"shared_rows", GreedyMethod::shared_rows}};
  for (const auto& [name, method] : greedy_methods) {
    benchmark::RegisterBenchmark((std::string("BM_ActionBlockGreedy/method:") + name).c_str(),
                                 BM_ActionBlockGreedy, method)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  for (const bool shared_rows : {false, true}) {
    benchmark::RegisterBenchmark(
        (std::string("BM_DeterministicShiftFit/method:") + (shared_rows ? "shared_rows" : "table"))
            .c_str(),
        BM_DeterministicShiftFit, shared_rows)
        ->ArgName("p")
        ->Arg(32)
        ->Arg(128)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  for (const bool pooled : {false, true}) {
    benchmark::RegisterBenchmark(
        (std::string("BM_UnitRowsFit/method:") + (pooled ? "pooled" : "shared_rows")).c_str(),
        BM_UnitRowsFit, pooled)
        ->ArgName("p")
        ->Arg(20)
        ->Arg(100)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  for (const bool prefix : {false, true}) {
    benchmark::RegisterBenchmark(
        (std::string("BM_KernelTablesOverCounts/method:") + (prefix ? "prefix" : "each")).c_str(),
        BM_KernelTablesOverCounts, prefix)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  for (const bool subtraction : {false, true}) {
    benchmark::RegisterBenchmark((std::string("BM_BrmRebuildAfterTheFirst/method:") +
                                  (subtraction ? "subtraction" : "direct"))
                                     .c_str(),
                                 BM_BrmRebuildAfterTheFirst, subtraction)
        ->ArgName("p")
        ->Arg(10)
        ->Arg(50)
        ->Arg(100)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  const std::pair<const char*, AssembleMethod> methods[] = {
      {"action_blocks", AssembleMethod::action_blocks},
      {"eigen_sparse_product", AssembleMethod::eigen_sparse_product}};
  for (const auto& [name, method] : methods) {
    benchmark::RegisterBenchmark((std::string("BM_AssembleBrmSystem/method:") + name).c_str(),
                                 BM_AssembleBrmSystem, method)
        ->ArgNames({"p", "truncation_e6"})
        ->Args({100, 1000})
        ->Args({200, 0})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  return true;
}();

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
