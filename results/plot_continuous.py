"""The figures of a continuous task (pendulum, mountain_car, acrobot, python_env:
any task of engine/tasks/continuous_protocol.hpp but the Khepera, which has its
own) from a ggk results file:

  <task>_steps.png   the paper's Fig. 3 / Fig. 6 form: mean test-episode length
                     and the share of episodes that ended (the task's ended
                     metric: success_rate, fall_fraction) against the number of
                     kernels, a curve per basis and solver, 95 % CIs over runs
  <task>_values.png  the paper's Fig. 2 form, for a task with a 2-D observation
                     (pendulum, mountain car, a 2-D python_env): V(s) = max_a Q(s, a) over the
                     observation box with GGK and with OGK side by side (one run,
                     one kernel count, one solver), each with its greedy
                     trajectory of test episode 0

    /usr/bin/python3 results/plot_continuous.py results/mountain-car.h5 results/figures \
        [--kernels P] [--run R] [--solver S] [--grid N]

V is computed here from the stored run as ggk's fits compute it
(engine/tasks/continuous_episodes.cpp): the observation divided by
observation_scale; GGK exp(-(ED(s, n(s)) + SP(n(s), c))^2 / 2 sigma^2) with n(s)
the nearest occupied SOM unit and SP the shortest path over the stored unit graph
(scipy.sparse.csgraph.dijkstra); OGK exp(-ED(s, c)^2 / 2 sigma^2) to the centre
units' prototypes; Q(s, a) = w_a . k(s) (the copy scheme). A test checks this
replay against the policy ggk stored at every SOM unit (unit_policy).
"""

import argparse
import sys
import tomllib
from pathlib import Path

import h5py
import matplotlib
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import (BASIS_STYLE, add_format_argument, legend_below,  # noqa: E402
                         metric_panels, metric_range, plot_metric, read_summary, run_group, save)

# The tasks' ended metric, what the test counts, and the observation's names.
TASKS = {
    "pendulum": ("fall_fraction", "episodes in which the pendulum fell (%)",
                 ("angle (rad)", "angular velocity (rad/s)")),
    "mountain_car": ("success_rate", "episodes that reached the goal (%)",
                     ("position", "velocity")),
    "acrobot": ("success_rate", "episodes that raised the tip above the bar (%)", None),
    # Any Gymnasium-API environment: the value figure where its observation is 2-D.
    "python_env": ("success_rate", "episodes that terminated (%)", ("dim_0", "dim_1")),
}


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def fig_steps(summary, task, out, job, fmt):
    ended, ended_label, _ = TASKS[task]
    test_max_steps = int(job[f"{task}.test_max_steps"])
    runs = len(set(summary["run"]))
    hue = ("basis", "solver")  # solvers by line style; plot_metric dodges every curve
    rows = metric_panels(summary, hue=hue)
    fig, axes = plt.subplots(len(rows), 2, figsize=(11, 4.8 * len(rows)), squeeze=False)
    panels = (("mean_steps", f"mean test-episode length (steps, at most {test_max_steps})"),
              (ended, ended_label))
    for column, (metric, label) in enumerate(panels):
        # The metric's whole range (0 to test_max_steps steps, 0-100 %).
        plot_metric(summary, metric, hue=hue, axes=axes[:, column], ylabel=label,
                    value_range=metric_range(metric, task, job))
    fig.suptitle(f"{task.replace('_', ' ')}, {runs} runs, greedy test episodes, 95 % CI")
    fig.tight_layout()
    saved = save(fig, out, f"{task}_steps", fmt, dpi=120)
    plt.close(fig)
    return saved


def fit_of(run, basis, kernels, solver):
    names = sorted(n for n in run[f"fits/{basis}"] if n.startswith(f"k_{kernels:04d}_")
                   and text(run[f"fits/{basis}/{n}"].attrs["solver"]) == solver)
    if not names:
        raise SystemExit(f"no {basis} fit with {kernels} kernels and {solver} in {run.name}")
    return run[f"fits/{basis}/{names[0]}"]


class StateKernels:
    """k(s) of a fit for scaled observations (rows), as ggk's fits compute it."""

    def __init__(self, run, fit):
        self.prototypes = run["som/prototypes"][:]
        self.occupied = run["graph/occupied"][:].astype(bool)
        self.centers = fit["centers"][:]
        self.sigma = float(fit.attrs["sigma"])
        self.basis = text(fit.attrs["basis"])
        g = run["graph"]
        n = len(g["indptr"]) - 1
        graph = csr_matrix((g["weights"][:], g["indices"][:], g["indptr"][:]), shape=(n, n))
        self.center_distances = dijkstra(graph, directed=False, indices=self.centers)

    def __call__(self, x):
        if self.basis == "ogk":
            d = np.linalg.norm(x[:, None, :] - self.prototypes[None, self.centers, :], axis=2)
        else:
            units = np.flatnonzero(self.occupied)
            to_units = np.linalg.norm(x[:, None, :] - self.prototypes[None, units, :], axis=2)
            nearest = np.argmin(to_units, axis=1)
            d = to_units[np.arange(len(x)), nearest][:, None] + \
                self.center_distances[:, units[nearest]].T
        return np.exp(-d ** 2 / (2.0 * self.sigma ** 2))


def q_values(run, fit, scaled):
    k = StateKernels(run, fit)(scaled)
    w = fit["weights"][:].reshape(-1, k.shape[1])
    return k @ w.T  # states x actions


def fig_values(f, task, out, run_index, kernels, solver, grid, fmt):
    run = run_group(f, task, run_index)
    scale = run["observation_scale"][:]
    observations = run["samples/observations"][:]
    lo, hi = observations.min(axis=0), observations.max(axis=0)
    xs, ys = np.linspace(lo[0], hi[0], grid), np.linspace(lo[1], hi[1], grid)
    mesh = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
    names = TASKS[task][2]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for ax, basis in zip(axes, ("ggk", "ogk")):
        fit = fit_of(run, basis, kernels, solver)
        values = q_values(run, fit, mesh / scale).max(axis=1).reshape(grid, grid)
        image = ax.pcolormesh(xs, ys, values, shading="auto", cmap="viridis")
        fig.colorbar(image, ax=ax, label="V(s) = max_a Q(s, a)")
        trajectory = fit["evaluation/trajectory_0"][:]
        ax.plot(trajectory[:, 0], trajectory[:, 1], color="w", linewidth=1.5,
                label="greedy test episode 0")
        ax.plot(trajectory[0, 0], trajectory[0, 1], "wo")
        ax.set_xlim(xs[0], xs[-1])
        ax.set_ylim(ys[0], ys[-1])
        ax.set_xlabel(names[0])
        ax.set_ylabel(names[1])
        ax.set_title(f"{BASIS_STYLE[basis][2]}, {kernels} kernels, {solver.upper()}, "
                     f"{len(trajectory) - 1} steps", fontsize=10)
        legend_below(ax, ncol=1)
    fig.suptitle(f"{task.replace('_', ' ')}: value functions of run {run_index} "
                 "over the observed box")
    fig.tight_layout()
    saved = save(fig, out, f"{task}_values", fmt, dpi=110)
    plt.close(fig)
    return saved


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("out_dir")
    parser.add_argument("--kernels", type=int, default=None,
                        help="kernel count of the value figure (default: the largest swept)")
    parser.add_argument("--run", type=int, default=0, help="run of the value figure")
    parser.add_argument("--solver", default=None,
                        help="solver of the value figure (default: lstdq if swept, else brm)")
    parser.add_argument("--grid", type=int, default=120, help="grid points per axis")
    add_format_argument(parser)
    args = parser.parse_args()
    with h5py.File(args.results, "r") as f:
        tasks = [t for t in TASKS if t in f]
        if not tasks:
            raise SystemExit(f"{args.results}: no continuous task ({', '.join(TASKS)})")
        task = tasks[0]
        job = tomllib.loads(text(f.attrs["job_resolved"]))
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary = read_summary(args.results, task)
    print(fig_steps(summary, task, out, job, args.format))
    with h5py.File(args.results, "r") as f:
        dimension = run_group(f, task, args.run)["samples/observations"].shape[1]
    if TASKS[task][2] is None or dimension != 2:
        return
    kernels = args.kernels or int(max(summary["kernels"]))
    swept = sorted(set(summary["solver"]))
    solver = args.solver or ("lstdq" if "lstdq" in swept else swept[0])
    with h5py.File(args.results, "r") as f:
        print(fig_values(f, task, out, args.run, kernels, solver, args.grid, args.format))


if __name__ == "__main__":
    main()
