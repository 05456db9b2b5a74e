"""The MPI hand-out of a job's runs, whole or with the last round in pieces
(engine/run/run_pieces.hpp), modelled from measured unit costs.

Input: a folder of one-run results files run<i>.h5 (ggk run JOB --runs i:i+1 -j 1),
times.txt (lines "i wall_seconds ..." from /usr/bin/time), and the stage seconds of
one run (samples, SOM, graph: the job with one cheap fit, divided by its runs).
A run's cost is its measured wall time; a piece's is the stage plus its groups'
share of the rest (each group of points sharing a basis table costs its fits'
fit_seconds plus, in proportion to them, the run's table building and tests).
The hand-out is simulated as the coordinator does it: the queue in order, each
unit to the rank free first (rank 0 computes too); the writer and the messages
are not counted (bench/README.md measures a hand-out at 8-21 ms).

    /usr/bin/python3 bench/mpi_pieces_model.py /tmp/units 0.94 2 4 8 16 32 64
"""
import heapq
import sys
from collections import OrderedDict
from pathlib import Path

import h5py


def run_groups(path):
    """(basis, kernels, sigma) -> fit seconds, in order of first point."""
    with h5py.File(path, "r") as f:
        task = f.attrs["task"]
        task = task.decode() if isinstance(task, bytes) else str(task)
        (run,) = [name for name in f[task] if name.startswith("run_")]
        rows = f[f"{task}/{run}/fit_metrics"][:]
    groups = OrderedDict()
    for row in sorted(rows, key=lambda r: r["sweep_point"]):
        key = (row["basis"], int(row["kernels"]), float(row["sigma"]))
        groups[key] = groups.get(key, 0.0) + float(row["fit_seconds"])
    return list(groups.values())


def pieces(group_costs, count):
    """Group indices per piece, dealt in snake order (run_pieces.cpp)."""
    k = min(count, len(group_costs))
    out = [[] for _ in range(k)]
    for g in range(len(group_costs)):
        lap, step = divmod(g, k)
        out[step if lap % 2 == 0 else k - 1 - step].append(g)
    return out


def units(runs, ranks, stage, split):
    """Unit costs in queue order."""
    total = len(runs)
    tail = total % ranks if (split and ranks > 1) else 0
    first_split = total - tail
    costs = []
    for u, (wall, groups) in enumerate(runs):
        if u < first_split:
            costs.append(wall)
            continue
        j = u - first_split
        count = ranks // tail + (1 if j < ranks % tail else 0)
        rest = wall - stage  # tables, fits and tests
        fitted = sum(groups)
        for piece in pieces(groups, count):
            share = sum(groups[g] for g in piece) / fitted
            costs.append(stage + rest * share)
    return costs


def makespan(costs, ranks):
    free = [0.0] * ranks
    heapq.heapify(free)
    end = 0.0
    for cost in costs:
        start = heapq.heappop(free)
        heapq.heappush(free, start + cost)
        end = max(end, start + cost)
    return end


def main():
    folder, stage, ranks_list = Path(sys.argv[1]), float(sys.argv[2]), sys.argv[3:]
    walls = {}
    for line in (folder / "times.txt").read_text().split("\n"):
        fields = line.split()
        if len(fields) >= 2 and fields[0].isdigit():
            walls[int(fields[0])] = float(fields[1])
    runs = [(walls[i], run_groups(folder / f"run{i}.h5")) for i in sorted(walls)]
    work = sum(wall for wall, _ in runs)
    print(f"{len(runs)} runs, {work:.1f} s of work (one core), stage {stage:.2f} s per run")
    print("| ranks | whole runs: wall s, efficiency | last round in pieces: wall s, efficiency |")
    print("|---|---|---|")
    for text in ranks_list:
        r = int(text)
        cells = []
        for split in (False, True):
            t = makespan(units(runs, r, stage, split), r)
            cells.append(f"{t:.2f}, {100 * work / (r * t):.0f} %")
        print(f"| {r} | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
