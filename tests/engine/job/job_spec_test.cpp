#include "engine/job/job_spec.hpp"

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(JobSpecNames, MatchJobFileSpelling) {
  EXPECT_EQ(kernel_type_name(KernelType::ggk), "ggk");
  EXPECT_EQ(kernel_type_name(KernelType::ogk), "ogk");
  EXPECT_EQ(solver_name(kernels::LspiSolver::brm), "brm");
  EXPECT_EQ(solver_name(kernels::LspiSolver::lstdq), "lstdq");
  EXPECT_EQ(basis_scheme_name(kernels::BasisScheme::shift), "shift");
  EXPECT_EQ(basis_scheme_name(kernels::BasisScheme::copy), "copy");
}

}  // namespace
}  // namespace ggk::engine
