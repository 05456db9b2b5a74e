// The proto-value functions' eigensolve (kernels/laplacian_eigensolver.hpp) on
// the graphs the paper's tasks make: run 0 of jobs/arm-paper.toml (the visited
// joint-grid poses, 50 x 1000 random moves) and of jobs/khepera-paper.toml (the
// occupied units of the 24 x 29 SOM), each as a normalized Laplacian with unit
// weights ([pvf] defaults), at p = 16, 32, 64 and 128 eigenpairs, one thread.
//
// BM_LaplacianEigenpairs/graph:{0 arm,1 khepera}/p: smallest_laplacian_eigenpairs
// (the CHOLMOD factorisation, the Lanczos iterations, the sign convention; the
// Laplacian is built once). Counters: nodes, edges, components, operator products.
// The peer is scipy.sparse.linalg.eigsh (ARPACK) on the same matrices:
// GGK_LAPLACIAN_DIR=DIR makes this benchmark write them there as Matrix Market
// files (arm.mtx, khepera.mtx, every digit) with its eigenvalues at p = 128
// (arm_values.txt, khepera_values.txt), for bench/scipy_eigsh_peer.py.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "kernels/graph_laplacian.hpp"
#include "kernels/laplacian_eigensolver.hpp"

namespace ggk::bench {
namespace {

const std::filesystem::path kJobs = std::filesystem::path(GGK_SOURCE_DIR) / "jobs";

struct TaskGraph {
  std::string name;
  kernels::GraphLaplacian laplacian;
  double edges = 0.0;
};

// Run 0 of the job with one cheap fit (its graph is what every fit sees).
TaskGraph task_graph(const std::string& name, const std::string& file, const std::string& nodes) {
  engine::JobLoadOptions options;
  options.check_output = false;
  options.overrides = {"runs=1", "sweep.basis=[\"ogk\"]", "sweep.kernels=[1]",
                       "sweep.solver=[\"brm\"]"};
  const engine::JobSpec job = engine::load_job_file(kJobs / file, engine::task_tables(), options);
  const engine::RunRecord record = engine::compute_run(job, 0);
  std::vector<std::uint8_t> is_node;
  for (const engine::NamedArray& array : record.arrays) {
    if (array.name == nodes) is_node.assign(array.values.begin(), array.values.end());
  }
  if (is_node.empty()) throw std::runtime_error(file + ": no " + nodes);
  TaskGraph graph{
      name,
      kernels::graph_laplacian(record.graph, is_node, kernels::LaplacianKind::normalized,
                               kernels::EdgeAffinity::unit),
      static_cast<double>(record.graph.num_arcs()) / 2.0};
  return graph;
}

void write_matrix_market(const TaskGraph& graph, const std::filesystem::path& dir) {
  std::ofstream out(dir / (graph.name + ".mtx"));
  const kernels::SparseColMatrix& m = graph.laplacian.matrix;
  out << "%%MatrixMarket matrix coordinate real general\n"
      << m.rows() << " " << m.cols() << " " << m.nonZeros() << "\n";
  char line[96];
  for (Eigen::Index c = 0; c < m.outerSize(); ++c) {
    for (kernels::SparseColMatrix::InnerIterator it(m, c); it; ++it) {
      std::snprintf(line, sizeof line, "%lld %lld %.17g\n", static_cast<long long>(it.row() + 1),
                    static_cast<long long>(c + 1), it.value());
      out << line;
    }
  }
  const kernels::LaplacianEigenpairs pairs =
      kernels::smallest_laplacian_eigenpairs(m, graph.laplacian.null_space, 128);
  std::ofstream values(dir / (graph.name + "_values.txt"));
  for (Eigen::Index j = 0; j < pairs.values.size(); ++j) {
    std::snprintf(line, sizeof line, "%.17g\n", pairs.values[j]);
    values << line;
  }
}

const std::vector<TaskGraph>& task_graphs() {
  static const std::vector<TaskGraph> graphs = [] {
    std::vector<TaskGraph> result;
    result.push_back(task_graph("arm", "arm-paper.toml", "graph/visited"));
    result.push_back(task_graph("khepera", "khepera-paper.toml", "graph/occupied"));
    if (const char* dir = std::getenv("GGK_LAPLACIAN_DIR")) {
      for (const TaskGraph& graph : result) write_matrix_market(graph, dir);
    }
    return result;
  }();
  return graphs;
}

void BM_LaplacianEigenpairs(benchmark::State& state) {
  const TaskGraph& graph = task_graphs()[static_cast<std::size_t>(state.range(0))];
  const auto p = static_cast<std::int32_t>(state.range(1));
  std::int32_t products = 0;
  for (auto _ : state) {
    const kernels::LaplacianEigenpairs pairs = kernels::smallest_laplacian_eigenpairs(
        graph.laplacian.matrix, graph.laplacian.null_space, p);
    if (!pairs.ok) state.SkipWithError(pairs.message.c_str());
    products = pairs.operator_products;
    benchmark::DoNotOptimize(pairs.vectors.data());
  }
  state.SetLabel(graph.name);
  state.counters["nodes"] = static_cast<double>(graph.laplacian.matrix.rows());
  state.counters["edges"] = graph.edges;
  state.counters["components"] = static_cast<double>(graph.laplacian.null_space.cols());
  state.counters["products"] = products;
}
BENCHMARK(BM_LaplacianEigenpairs)
    ->ArgNames({"graph", "p"})
    ->ArgsProduct({{0, 1}, {16, 32, 64, 128}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
