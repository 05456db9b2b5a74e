"""Peer comparison: one LSPI fit (BRM and LSTD-Q, at most 20 iterations) written
with numpy / scipy on the same problem and features as BM_FitLspi in
bench/lspi_benchmark.cpp: a 40 x 40 grid world (1,600 states x 4 actions, one
deterministic successor per pair, weights 1 + (31 s + 17 a) mod 40, goal in the
last corner), p = 100 geodesic Gaussian centres spread over the node ids
(sigma 5, truncated at 1e-3), shift basis (k = 400). A and b are formed from the
sparse Psi (scipy.sparse products), solved dense (scipy.linalg, Cholesky for BRM,
LU for LSTD-Q), the greedy policy by numpy's argmax (ties to the lowest action).
BLAS at one thread (set before numpy loads). Prints the median of 5 fits.

    /usr/bin/python3 bench/numpy_lspi_peer.py
"""

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_name] = "1"

import time  # noqa: E402

import numpy as np  # noqa: E402
import scipy.linalg as la  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from scipy.sparse.csgraph import dijkstra  # noqa: E402

SIDE, ACTIONS, SIGMA, GAMMA, RIDGE, MAX_ITERATIONS = 40, 4, 5.0, 0.9, 1e-6, 20


def grid_graph(rows, cols):
    ids = np.arange(rows * cols).reshape(rows, cols)
    right = np.stack([ids[:, :-1].ravel(), ids[:, 1:].ravel()])
    down = np.stack([ids[:-1, :].ravel(), ids[1:, :].ravel()])
    edges = np.concatenate([right, down], axis=1)
    u = np.concatenate([edges[0], edges[1]])
    v = np.concatenate([edges[1], edges[0]])
    return sp.csr_matrix((np.ones(len(u)), (u, v)), shape=(rows * cols, rows * cols))


def make_problem(p):
    n_states = SIDE * SIDE
    goal = n_states - 1
    s = np.repeat(np.arange(n_states), ACTIONS)
    a = np.tile(np.arange(ACTIONS), n_states)
    r_, c_ = s // SIDE, s % SIDE
    nr = np.clip(r_ + np.where(a == 0, -1, np.where(a == 1, 1, 0)), 0, SIDE - 1)
    nc = np.clip(c_ + np.where(a == 2, -1, np.where(a == 3, 1, 0)), 0, SIDE - 1)
    nxt = nr * SIDE + nc
    terminal = (nxt == goal) & (s != goal)
    reward = terminal.astype(float)
    weight = 1.0 + ((31 * s + 17 * a) % 40)
    centers = (np.arange(p, dtype=np.int64) * n_states // p).astype(np.int32)
    distances = dijkstra(grid_graph(SIDE, SIDE), directed=True, indices=centers)  # p x N
    kernels = np.exp(-(distances.T ** 2) / (2.0 * SIGMA * SIGMA))  # N x p
    kernels[~(kernels >= 1e-3)] = 0.0
    # Shift basis with deterministic successors: phi(s, a) = K(s'(s, a)) in block a.
    rows = np.repeat(np.arange(n_states * ACTIONS), p)
    cols = (a[:, None] * p + np.arange(p)[None, :]).ravel()
    vals = kernels[nxt].ravel()
    features = sp.csr_matrix((vals, (rows, cols)), shape=(n_states * ACTIONS, ACTIONS * p))
    features.eliminate_zeros()
    return features, s, a, reward, nxt, terminal, weight


def fit_lspi(features, s, a, reward, nxt, terminal, weight, brm):
    n_states = features.shape[0] // ACTIONS
    sqrt_w = np.sqrt(weight)
    phi = sp.diags(sqrt_w) @ features[s * ACTIONS + a]
    rhs_r = sqrt_w * reward
    on_samples = np.zeros(n_states, dtype=bool)
    on_samples[s] = True
    on_samples[nxt[~terminal]] = True
    policy = np.zeros(n_states, dtype=np.int64)
    live = np.where(terminal, 0.0, 1.0)
    for iteration in range(1, MAX_ITERATIONS + 1):
        nxt_phi = sp.diags(sqrt_w * live) @ features[nxt * ACTIONS + policy[nxt]]
        if brm:
            psi = phi - GAMMA * nxt_phi
            a_mat = (psi.T @ psi).toarray() + RIDGE * np.eye(features.shape[1])
            b_vec = psi.T @ rhs_r
            w = la.cho_solve(la.cho_factor(a_mat, lower=True), b_vec)
        else:
            a_mat = (phi.T @ (phi - GAMMA * nxt_phi)).toarray() + RIDGE * np.eye(features.shape[1])
            b_vec = phi.T @ rhs_r
            w = la.lu_solve(la.lu_factor(a_mat), b_vec)
        q = (features @ w).reshape(n_states, ACTIONS)
        improved = np.argmax(q, axis=1)
        changes = int(np.count_nonzero(on_samples & (improved != policy)))
        policy = improved
        if changes == 0:
            break
    return w, iteration


def main():
    features, *samples = make_problem(100)
    print(f"k = {features.shape[1]}, {len(samples[0])} samples, "
          f"{features.nnz / features.shape[0]:.1f} non-zeros per feature row")
    for brm in (True, False):
        times, iterations = [], 0
        for _ in range(5):
            start = time.perf_counter()
            _, iterations = fit_lspi(features, *samples, brm=brm)
            times.append(time.perf_counter() - start)
        print(f"numpy/scipy fit_lspi {'brm' if brm else 'lstdq'} p:100 k:400 truncation 1e-3  "
              f"median {1000 * np.median(times):.1f} ms  ({iterations} iterations, "
              f"{1000 * np.median(times) / iterations:.2f} ms per iteration)")


if __name__ == "__main__":
    main()
