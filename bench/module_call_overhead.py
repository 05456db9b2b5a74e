"""The Python module's per-call overhead: each call of bench/module_call_benchmark.cpp
made through `import ggk` on the same inputs, side by side with the C++ call (the
benchmark binary, run here in the same session). Prints the medians and the
difference (the binding's cost: argument conversion, the GIL released and taken
back, the result wrapped as numpy / scipy.sparse).

    /usr/bin/python3 bench/module_call_overhead.py [build]
"""

import json
import os
import subprocess
import sys
import timeit
from pathlib import Path

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ[_name] = "1"

BUILD = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / "build")
sys.path.insert(0, str(BUILD / "python"))
import numpy as np  # noqa: E402

import ggk  # noqa: E402


def path_graph(n):
    return ggk.graph_from_edges(n, np.arange(n - 1, dtype=np.int32),
                                np.arange(1, n, dtype=np.int32), np.ones(n - 1))


def chain(n):
    positions = (np.arange(n) / (n - 1))[:, None]
    table = ggk.ordinary_kernels(positions, (np.arange(5) / 4.0)[:, None], 0.25)
    s = np.repeat(np.arange(n), 2)
    a = np.tile([0, 1], n)
    nxt = np.where(a == 0, np.maximum(s - 1, 0), np.minimum(s + 1, n - 1))
    end = (nxt == n - 1) & (s != n - 1)
    return ggk.copy_basis(table, 2), ggk.Samples(s, a, end.astype(float), nxt, end)


def python_cases():
    cases = {}
    for n in (16, 4096):
        graph, sources = path_graph(n), np.array([0], dtype=np.int32)
        cases[f"BM_CallShortestPaths/{n}"] = lambda g=graph, s=sources: ggk.shortest_paths(g, s)
    x = np.array([[0.3, 0.7]])
    centers = np.repeat((np.arange(40) / 40.0)[:, None], 2, axis=1)
    cases["BM_CallOrdinaryKernels/40"] = lambda: ggk.ordinary_kernels(x, centers, 0.5)
    for n in (20, 2000):
        basis, samples = chain(n)
        cases[f"BM_CallLspi/{n}"] = lambda b=basis, s=samples: ggk.lspi(s, b, ridge=1e-6)
    return cases


def median_seconds(call, repeats=7):
    number, _ = timeit.Timer(call).autorange()
    return float(np.median([t / number for t in timeit.repeat(call, number=number,
                                                              repeat=repeats)]))


def main():
    report = subprocess.run(
        [str(BUILD / "bench" / "module_call_benchmark"), "--benchmark_format=json",
         "--benchmark_repetitions=7", "--benchmark_report_aggregates_only=true"],
        check=True, capture_output=True, text=True)
    cpp = {b["run_name"]: b["real_time"] for b in json.loads(report.stdout)["benchmarks"]
           if b.get("aggregate_name") == "median"}
    print(f"{'call':28} {'C++ us':>10} {'Python us':>10} {'overhead us':>12} {'ratio':>7}")
    for name, call in python_cases().items():
        python_us = 1e6 * median_seconds(call)
        print(f"{name:28} {cpp[name]:10.2f} {python_us:10.2f} {python_us - cpp[name]:12.2f} "
              f"{python_us / cpp[name]:7.2f}")


if __name__ == "__main__":
    main()
