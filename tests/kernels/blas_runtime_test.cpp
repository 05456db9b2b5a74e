#include "kernels/blas_runtime.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {
namespace {

TEST(BlasRuntime, TheInstalledBlasIsSafeToCallConcurrently) {
  const BlasInfo info = blas_info();
  EXPECT_TRUE(info.concurrent_safe) << info.name;
  EXPECT_FALSE(info.name.empty());
  // The LAPACK library is named (by the path it was loaded from).
  EXPECT_NE(info.name.find("; LAPACK from /"), std::string::npos) << info.name;
}

// Products of the sizes LSPI forms (GEMM and SYRK through EIGEN_USE_BLAS), on four
// threads at once, equal the same products formed on one thread, bit for bit. A
// BLAS without locking (Debian's serial OpenBLAS) fails this within a few thousand
// calls; a BLAS that splits calls over threads of its own may too.
TEST(BlasRuntime, ConcurrentProductsEqualSequentialOnesBitForBit) {
  use_calling_thread_blas();
  struct Case {
    Eigen::MatrixXd u, v, gemm, syrk;
  };
  std::vector<Case> cases;
  for (int c = 0; c < 24; ++c) {
    const Eigen::Index n = 7 + 41 * c, p = 4 + 5 * (c % 9);
    Case item{Eigen::MatrixXd::Random(n, p), Eigen::MatrixXd::Random(n, p), {}, {}};
    item.gemm.noalias() = item.u.transpose() * item.v;
    item.syrk = Eigen::MatrixXd::Zero(p, p);
    item.syrk.selfadjointView<Eigen::Lower>().rankUpdate(item.u.transpose());
    cases.push_back(std::move(item));
  }
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int round = 0; round < 60; ++round) {
        for (std::size_t c = 0; c < cases.size(); ++c) {
          const Case& item = cases[(c + static_cast<std::size_t>(t)) % cases.size()];
          Eigen::MatrixXd gemm(item.u.cols(), item.v.cols());
          gemm.noalias() = item.u.transpose() * item.v;
          Eigen::MatrixXd syrk = Eigen::MatrixXd::Zero(item.u.cols(), item.u.cols());
          syrk.selfadjointView<Eigen::Lower>().rankUpdate(item.u.transpose());
          if (gemm != item.gemm || syrk != item.syrk) mismatches.fetch_add(1);
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(mismatches.load(), 0) << blas_info().name;
}

}  // namespace
}  // namespace ggk::kernels
