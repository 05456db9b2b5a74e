#include "engine/job/sweep.hpp"

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(ExpandSweep, CartesianProductWithLambdaFastest) {
  JobSpec job;
  job.sweep.basis = {KernelType::ogk, KernelType::ggk};
  job.sweep.kernels = {8, 4, 16};
  job.sweep.sigma = {2.0};
  job.sweep.solver = {kernels::LspiSolver::brm, kernels::LspiSolver::lstdq};
  job.sweep.lambda = {0.0, 1e-6};
  const std::vector<SweepPoint> points = expand_sweep(job);
  ASSERT_EQ(points.size(), 2u * 3u * 1u * 2u * 2u);

  // Brute-force mixed-radix decoding of each index, in the documented order.
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::size_t rest = i;
    const std::size_t lambda = rest % 2;
    rest /= 2;
    const std::size_t solver = rest % 2;
    rest /= 2;
    const std::size_t sigma = rest % 1;
    rest /= 1;
    const std::size_t kernels = rest % 3;
    rest /= 3;
    const std::size_t basis = rest;
    const SweepPoint& point = points[i];
    EXPECT_EQ(point.index, static_cast<std::int32_t>(i));
    EXPECT_EQ(point.basis, job.sweep.basis[basis]);
    EXPECT_EQ(point.kernels, job.sweep.kernels[kernels]);
    EXPECT_EQ(point.sigma, job.sweep.sigma[sigma]);
    EXPECT_EQ(point.solver, job.sweep.solver[solver]);
    EXPECT_EQ(point.lambda, job.sweep.lambda[lambda]);
  }
  // Spelled out for the first points: values keep the job file's order.
  EXPECT_EQ(points[0].basis, KernelType::ogk);
  EXPECT_EQ(points[0].kernels, 8);
  EXPECT_EQ(points[0].lambda, 0.0);
  EXPECT_EQ(points[1].lambda, 1e-6);
  EXPECT_EQ(points[2].solver, kernels::LspiSolver::lstdq);
  EXPECT_EQ(points[4].kernels, 4);
  EXPECT_EQ(points[12].basis, KernelType::ggk);
}

TEST(ExpandSweep, EmptyAxisGivesNoPoints) {
  JobSpec job;
  job.sweep.basis = {KernelType::ggk};
  job.sweep.kernels = {4};
  job.sweep.sigma = {};
  job.sweep.solver = {kernels::LspiSolver::brm};
  job.sweep.lambda = {0.0};
  EXPECT_TRUE(expand_sweep(job).empty());
}

}  // namespace
}  // namespace ggk::engine
