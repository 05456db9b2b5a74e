#include "engine/job/sweep.hpp"

namespace ggk::engine {

std::vector<SweepPoint> expand_sweep(const JobSpec& job) {
  const SweepAxes& axes = job.sweep;
  std::vector<SweepPoint> points;
  points.reserve(axes.basis.size() * axes.kernels.size() * axes.sigma.size() * axes.solver.size() *
                 axes.lambda.size());
  // Nested loops, outermost first: the last axis (lambda) varies fastest.
  for (const KernelType basis : axes.basis) {
    for (const std::int32_t kernel_count : axes.kernels) {
      for (const double sigma : axes.sigma) {
        for (const kernels::LspiSolver solver : axes.solver) {
          for (const double lambda : axes.lambda) {
            const auto index = static_cast<std::int32_t>(points.size());
            points.push_back(
                {index, basis, kernel_count, sigma, solver, lambda, 0, job.lspi, {}, {}});
          }
        }
      }
    }
  }
  return points;
}

kernels::LspiOptions lspi_options(const SweepPoint& point) {
  const LspiSettings& lspi = point.lspi;
  kernels::LspiOptions options;
  options.gamma = lspi.gamma;
  options.ridge = point.lambda;
  options.ridge_scale = lspi.ridge;
  options.max_iterations = lspi.max_iterations;
  options.solver = point.solver;
  options.solver_settings.min_rcond = lspi.min_rcond;
  options.stopping = lspi.stopping;
  options.weight_tolerance = lspi.weight_tolerance;
  options.keep_iterates = lspi.evaluate_iterations;
  options.linear_algebra = lspi.linear_algebra;
  return options;
}

}  // namespace ggk::engine
