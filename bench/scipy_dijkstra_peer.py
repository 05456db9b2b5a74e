"""Peer comparison: scipy.sparse.csgraph.dijkstra on the same grid graphs and
sources as bench/dijkstra_benchmark (one thread). Prints the median of 5 runs.

    /usr/bin/python3 bench/scipy_dijkstra_peer.py
"""

import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra


def grid_graph(rows, cols):
    ids = np.arange(rows * cols).reshape(rows, cols)
    right = np.stack([ids[:, :-1].ravel(), ids[:, 1:].ravel()])
    down = np.stack([ids[:-1, :].ravel(), ids[1:, :].ravel()])
    edges = np.concatenate([right, down], axis=1)
    u = np.concatenate([edges[0], edges[1]])
    v = np.concatenate([edges[1], edges[0]])
    return sp.csr_matrix((np.ones(len(u)), (u, v)), shape=(rows * cols, rows * cols))


def spread_sources(n, p):
    return (np.arange(p, dtype=np.int64) * n // p).astype(np.int32)


for rows, cols, p in [(37, 72, 100), (360, 360, 16)]:
    graph = grid_graph(rows, cols)
    sources = spread_sources(rows * cols, p)
    times = []
    for _ in range(5):
        start = time.perf_counter()
        dijkstra(graph, directed=True, indices=sources)
        times.append(time.perf_counter() - start)
    print(f"scipy dijkstra rows:{rows}/cols:{cols}/p:{p}  median {1000 * np.median(times):.1f} ms")
