#!/usr/bin/env python3
"""Peer of bench/laplacian_eigensolver_benchmark.cpp: scipy.sparse.linalg.eigsh
(ARPACK) on the same Laplacians, for the p smallest eigenpairs, in shift-invert
mode at the same small negative shift ggk uses (-1e-3 x the largest diagonal
entry: shift-invert at 0 meets a singular matrix; which='SM' does not converge
on a Laplacian, scipy #6339), tol 1e-13 as ggk's Lanczos. ARPACK finds the
zero eigenvalues too (ggk puts the components' indicators first and deflates
them), so each call asks for p. Checks the eigenvalues against ggk's at p = 128.

  GGK_LAPLACIAN_DIR=DIR build/bench/laplacian_eigensolver_benchmark --benchmark_filter=x
  OPENBLAS_NUM_THREADS=1 /usr/bin/python3 bench/scipy_eigsh_peer.py DIR [REPEATS]

Prints graph, p, the median wall time of REPEATS (default 5) calls in ms, and
the largest |lambda_scipy - lambda_ggk| at p = 128.
"""

import sys
import time
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse.linalg


def main():
    folder = Path(sys.argv[1])
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    for name in ("arm", "khepera"):
        laplacian = scipy.sparse.csc_matrix(scipy.io.mmread(folder / f"{name}.mtx"))
        shift = -1e-3 * laplacian.diagonal().max()
        ggk_values = np.loadtxt(folder / f"{name}_values.txt")
        for p in (16, 32, 64, 128):
            times = []
            for _ in range(repeats):
                started = time.perf_counter()
                values = scipy.sparse.linalg.eigsh(laplacian, k=p, sigma=shift, which="LM",
                                                   tol=1e-13, return_eigenvectors=True,
                                                   v0=np.ones(laplacian.shape[0]))[0]
                times.append(time.perf_counter() - started)
            values = np.sort(values)
            line = f"{name:8s} n={laplacian.shape[0]:5d} p={p:4d} {1e3 * np.median(times):9.2f} ms"
            if p == len(ggk_values):
                line += f"  max |lambda - ggk| = {np.max(np.abs(values - ggk_values)):.2e}"
            print(line)


if __name__ == "__main__":
    main()
