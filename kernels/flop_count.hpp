#pragma once
// A count of the floating-point operations of the dense work an LSPI fit does
// through BLAS and LAPACK: the group products of the action-block system
// (action_block_system.cpp: its start blocks, C_xy = U^T V, the rank updates of
// V^T V and their non-zero counts, the right-hand sides) and the dense solves'
// factorizations (dense_solvers.cpp: dpotrf, dgetrf), each counted as the call's
// textbook count (2 m n k for a product, n k (n + 1) for a rank-k update, n^3 / 3
// for a Cholesky factor, 2 n^3 / 3 for an LU one). What the work would cost at the
// single-core dgemm peak is the bound that bench/README.md's limit analysis
// measures the jobs against (bench/lspi_benchmark: BM_PaperRun). A diagnostic:
// never a result, never written to a file.
//
// Thread-safe (one relaxed atomic); the process's total since it started.

#include <cstdint>

namespace ggk::kernels {

void count_flops(double flops);
double flops_counted();

}  // namespace ggk::kernels
