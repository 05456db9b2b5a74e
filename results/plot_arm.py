"""The robot-arm figures of the paper (sec. 4.1) from a ggk results file:

  arm_state_space.png   Fig. 1(b): joint space, colliding poses, goals, start A
  arm_values.png        Fig. 2: V(s) = max_a Q(s, a) for GGK and OGK (one run, one
                        kernel count) with the greedy trajectory from A
  arm_success.png       Fig. 3: success vs number of kernels, GGK vs OGK (and PVF where run), 95 % CIs
                        over runs (from A, and from every free pose)

    /usr/bin/python3 results/plot_arm.py results/arm-paper.h5 results/figures [--kernels P] [--run R]
        [--format png|pdf|svg]

Fig. 3 gets a row of panels per value of every swept axis besides kernels and
basis (solver, sigma, lambda): no axis is pooled. Success from A is a 0/1 outcome
per run: its intervals are Wilson's; success from all poses uses Student's t.
"""

import argparse
import sys
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import ListedColormap, SymLogNorm  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import (BASIS_STYLE, add_format_argument, metric_panels,  # noqa: E402
                         plot_metric, read_summary, run_group, save, select_where)


def grid_axes(run_group):
    """(state_of grid, shoulder angles, elbow angles) in degrees. graph/nodes holds
    the joint angles / 5 at any grid step ([arm] grid_step_degrees, default 5);
    the step is read off two free cells in different rows or columns."""
    state_of = run_group["grid/state_of"][:].astype(int)
    nodes = run_group["graph/nodes"][:]
    cells = np.argwhere(state_of >= 0)
    angles = 5 * nodes[state_of[cells[:, 0], cells[:, 1]]]  # (free cells, 2) in degrees
    step = 5.0  # a grid of one free cell has no step to read; any will do
    for axis in (0, 1):
        moved = np.flatnonzero(cells[:, axis] != cells[0, axis])
        if moved.size:
            k = moved[0]
            step = (angles[k, axis] - angles[0, axis]) / (cells[k, axis] - cells[0, axis])
            step = round(step * 10) / 10  # steps are whole tenths of a degree
            break
    shoulders = angles[0, 0] + step * (np.arange(state_of.shape[0]) - cells[0, 0])
    elbows = angles[0, 1] + step * (np.arange(state_of.shape[1]) - cells[0, 1])
    return state_of, shoulders, elbows


def on_grid(state_of, per_state):
    grid = np.full(state_of.shape, np.nan)
    free = state_of >= 0
    grid[free] = per_state[state_of[free]]
    return grid


def trajectory_angles(nodes, trajectory):
    states = np.asarray(trajectory, dtype=int)
    return 5 * nodes[states, 1], 5 * nodes[states, 0]  # (elbow, shoulder)


def extent(shoulders, elbows):
    """imshow's extent: each cell centred on its angles, half a grid step each side."""
    half = (shoulders[1] - shoulders[0]) / 2 if len(shoulders) > 1 else (
        (elbows[1] - elbows[0]) / 2 if len(elbows) > 1 else 2.5)
    return [elbows[0] - half, elbows[-1] + half, shoulders[0] - half, shoulders[-1] + half]


def fit_groups(run, basis, kernels):
    """The fit groups of `kernels` kernels (several when the job sweeps other
    axes: fit group names hold every axis value), sorted by name."""
    return sorted(n for n in run[f"fits/{basis}"] if n.startswith(f"k_{kernels:04d}_"))


def configuration_label(summary, configuration):
    """' (study: key=value, ...)' of the run configuration the run figures show,
    '' for a plain job's file."""
    if "configuration" not in summary:
        return ""
    rows = summary["configuration"] == (configuration or 0)
    axes = [c for c in summary if "." in c and c != "configuration"]
    values = [f"{axis}={summary[axis][rows][0]}" for axis in axes if rows.any()]
    return f" (study configuration {configuration or 0}: {', '.join(values)})" if values else ""


def fig_state_space(f, out, fmt, configuration, label):
    run = run_group(f, "arm", None, configuration=configuration)
    state_of, shoulders, elbows = grid_axes(run)
    goal = run["grid/goal"][:] > 0
    image = np.where(state_of < 0, 1, 0) + np.where(goal, 2, 0)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.imshow(image, origin="lower", extent=extent(shoulders, elbows), aspect="auto",
              cmap=ListedColormap(["white", "0.45", "tab:orange"]), vmin=0, vmax=2,
              interpolation="nearest")
    first_fit = next(iter(run["fits/ggk"].values()))
    if "trajectory_A" in first_fit:
        nodes = run["graph/nodes"][:]
        e, s = trajectory_angles(nodes, first_fit["trajectory_A"][:][:1])
        ax.plot(e, s, "k*", markersize=14, label="start A")
    ax.plot([], [], "s", color="0.45", label="collision")
    ax.plot([], [], "s", color="tab:orange", label=f"goal ({int(goal.sum())} states)")
    ax.set_xlabel("elbow angle (deg)")
    ax.set_ylabel("shoulder angle (deg)")
    ax.set_title(f"arm joint space: {int((state_of >= 0).sum())} free poses{label}", fontsize=10)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    path = save(fig, out, "arm_state_space", fmt)
    plt.close(fig)
    return path


def fig_values(f, out, kernels, run_index, fmt, configuration, label):
    run = run_group(f, "arm", run_index, configuration=configuration)
    state_of, shoulders, elbows = grid_axes(run)
    nodes = run["graph/nodes"][:]
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.5))
    for ax, basis in zip(axes, ("ggk", "ogk")):
        names = fit_groups(run, basis, kernels)
        if not names:
            sys.exit(f"plot_arm.py: run {run_index} has no {basis} fit with {kernels} kernels")
        fit = run[f"fits/{basis}/{names[0]}"]
        shown = f" ({names[0]})" if len(names) > 1 else ""
        values = on_grid(state_of, fit["state_values"][:])
        # V spans 0.9^80 .. 1: a symmetric log scale shows the far slopes too.
        im = ax.imshow(values, origin="lower", extent=extent(shoulders, elbows), aspect="auto",
                       cmap="viridis", interpolation="nearest",
                       norm=SymLogNorm(linthresh=1e-3, vmin=np.nanmin(values),
                                       vmax=np.nanmax(values)))
        fig.colorbar(im, ax=ax, label="V(s) = max_a Q(s, a) (symmetric log scale)")
        e, s = trajectory_angles(nodes, fit["trajectory_A"][:])
        ax.plot(e, s, "w-", linewidth=2)
        ax.plot(e[:1], s[:1], "w*", markersize=14)
        reached = fit.attrs["success_from_A"] == 1
        ax.set_title(f"{BASIS_STYLE[basis][2]}, {kernels} kernels{shown}: from A "
                     f"{'reaches the goal' if reached else 'fails'}", fontsize=10)
        ax.set_xlabel("elbow angle (deg)")
        ax.set_ylabel("shoulder angle (deg)")
    if label:
        fig.suptitle(f"run {run_index}{label}", fontsize=10)
    fig.tight_layout()
    path = save(fig, out, "arm_values", fmt)
    plt.close(fig)
    return path


def fig_success(summary, out, fmt):
    runs = len(set(summary["run"]))
    # A row per value of every swept axis besides kernels and basis (a study's
    # too): plot_metric draws one metric into each column, dodged, on 0-100 %.
    rows = metric_panels(summary)
    fig, axes = plt.subplots(len(rows), 2, figsize=(11, 4.4 * len(rows)), squeeze=False)
    metrics = (("success_from_A", "success from A (% of runs, Wilson CI)"),
               ("success_rate", "success from all free poses (%, t CI)"))
    for column, (metric, label) in enumerate(metrics):
        plot_metric(summary, metric, axes=axes[:, column], ylabel=label)
    fig.suptitle(f"robot arm, {runs} runs, 95 % CI")
    fig.tight_layout()
    saved = save(fig, out, "arm_success", fmt)
    plt.close(fig)
    return saved


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("out_dir")
    parser.add_argument("--kernels", type=int, default=None,
                        help="kernel count of Fig. 2 (default: the largest swept)")
    parser.add_argument("--run", type=int, default=0, help="run shown in Fig. 2")
    parser.add_argument("--where", action="append", default=[], metavar="KEY=VALUE",
                        help="a study's file: the run configuration with these values of its "
                             "axes (e.g. --where arm.grid_step_degrees=5; repeatable); without "
                             "it the run figures show the first and say which")
    add_format_argument(parser)
    args = parser.parse_args()
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary, configuration = select_where(read_summary(args.results, "arm"), args.where)
    label = configuration_label(summary, configuration)
    with h5py.File(args.results, "r") as f:
        kernels = args.kernels
        if kernels is None:
            kernels = int(max(summary["kernels"]))
        paths = [fig_state_space(f, out, args.format, configuration, label),
                 fig_values(f, out, kernels, args.run, args.format, configuration, label)]
    paths.append(fig_success(summary, out, args.format))
    for path in paths:
        print(path)


if __name__ == "__main__":
    main()
