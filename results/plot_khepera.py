"""The Khepera figures of the paper (sec. 4.2) from a ggk results file:

  khepera_graph.png         Fig. 4(b): the SOM graph over the units, projected to
                            2-D by PCA of the unit prototypes (8-D IR readings);
                            only edges lighter than --edge-threshold are drawn
  khepera_policies.png      Fig. 5: greedy action per SOM unit, GGK and OGK (one
                            run, one kernel count), laid out as in Fig. 4(b)
  khepera_return.png        Fig. 6: mean evaluation return vs number of kernels,
                            GGK vs OGK (and PVF where run), 95 % CIs over runs (and the fraction of
                            evaluation episodes stopped by a collision)
  khepera_trajectories.png  the arena with the GGK and OGK evaluation trajectories
                            (one run, one kernel count, every episode)

    /usr/bin/python3 results/plot_khepera.py results/khepera-paper.h5 results/figures \
        [--kernels P] [--run R] [--solver S] [--edge-threshold W] [--arena ARENA.toml]
        [--prefix NAME] [--where KEY=VALUE]

A study's file (jobs/README.md, Studies) shows one run configuration with --where
(`--where khepera.motion.turn_deg=45`); without it Fig. 6 has a row of panels per
configuration and the run figures show the first.
Figs. 5 and the trajectories show one solver (--solver, default brm); Fig. 6 has a
curve per basis and solver. --prefix replaces "khepera" in the file names.

The arena comes from the job stored in the file (root attribute `job`): inline
`[khepera.arena]`, or `[khepera] arena_file` relative to the job file (root
attribute `job_file`, looked up as given, then from the results file's folder and
from the repository root); --arena overrides it.
"""

import argparse
import math
import sys
import tomllib
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import patches  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import (BASIS_STYLE, add_format_argument, job_settings,  # noqa: E402
                         metric_panels, metric_range, plot_metric, read_summary, run_group,
                         save, select_where)

FORMAT = "png"  # --format: the file type of every figure
CONFIGURATION = None  # --where: the study's run configuration shown (None: a plain job's runs)

# Actions of sims/khepera (motion.hpp): symbol and colour as in paper Fig. 5.
ACTIONS = [("\u2191", "forward", "tab:green"), ("\u2190", "rotate left", "tab:blue"),
           ("\u2192", "rotate right", "tab:orange"), ("\u2193", "backward", "tab:red")]
# s0..s7 of sims/khepera/robot.hpp, for the PCA loadings.
SENSORS = ["s0 L", "s1 FL", "s2 F", "s3 F", "s4 FR", "s5 R", "s6 B", "s7 B"]
REPO = Path(__file__).resolve().parent.parent


# ---------------------------------------------------------------- reading ----

def text(value):
    """An HDF5 string attribute as str (h5py gives bytes or str by how it was stored)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def fit_group(run, basis, kernels, solver):
    """The fit of `basis` with `kernels` centres and `solver` (the first if other
    axes were swept)."""
    names = sorted(n for n in run[f"fits/{basis}"] if n.startswith(f"k_{kernels:04d}_")
                   and text(run[f"fits/{basis}/{n}"].attrs["solver"]) == solver)
    if not names:
        sys.exit(f"no {basis} fit with {kernels} kernels and {solver} in {run.name}")
    return run[f"fits/{basis}/{names[0]}"]


def job_config(f):
    return tomllib.loads(text(f.attrs["job"]))


def read_arena(f, results_path, override=None):
    """The arena table ([khepera.arena] or the arena file's top level)."""
    if override is not None:
        return tomllib.loads(Path(override).read_text())
    khepera = job_config(f).get("khepera", {})
    if "arena" in khepera:
        return khepera["arena"]
    relative = Path(khepera["arena_file"])
    job_file = Path(str(f.attrs.get("job_file", "job.toml")))
    candidates = [job_file.parent / relative,
                  Path(results_path).resolve().parent / job_file.parent / relative,
                  REPO / job_file.parent / relative,
                  REPO / "jobs" / relative]
    for path in candidates:
        if path.is_file():
            return tomllib.loads(path.read_text())
    sys.exit(f"arena file {relative} of job {job_file} not found (tried "
             f"{', '.join(str(c) for c in candidates)}); pass --arena")


def pca_layout(prototypes, occupied):
    """2-D coordinates of every unit from the principal axes of the occupied
    units' prototypes, the explained variance fractions and the loadings (2 x 8).
    Axis signs are fixed so that each axis' largest loading is positive."""
    data = prototypes[occupied]
    mean = data.mean(axis=0)
    _, s, vt = np.linalg.svd(data - mean, full_matrices=False)
    axes = vt[:2]
    axes *= np.sign(axes[np.arange(2), np.abs(axes).argmax(axis=1)])[:, None]
    explained = s[:2] ** 2 / np.sum(s ** 2)
    return (prototypes - mean) @ axes.T, explained, axes


def graph_edges(run, threshold):
    """Undirected edges (i < j) of the unit graph and their weights."""
    indptr = run["graph/indptr"][:]
    indices = run["graph/indices"][:]
    weights = run["graph/weights"][:]
    rows = np.repeat(np.arange(len(indptr) - 1), np.diff(indptr))
    keep = rows < indices
    i, j, w = rows[keep], indices[keep], weights[keep]
    light = w < threshold
    return i[light], j[light], w[light], int(keep.sum())


# ---------------------------------------------------------------- figures ----

def draw_loadings(ax, coords, loadings):
    """The sensors' directions in the PCA plane, as a small biplot in the corner."""
    span = np.ptp(coords, axis=0).max()
    origin = coords.min(axis=0) + 0.1 * np.ptp(coords, axis=0)
    scale = 0.12 * span / np.abs(loadings).max()
    for d, label in enumerate(SENSORS):
        dx, dy = scale * loadings[0, d], scale * loadings[1, d]
        if math.hypot(dx, dy) < 0.15 * scale:
            continue
        ax.annotate("", xy=(origin[0] + dx, origin[1] + dy), xytext=origin,
                    arrowprops=dict(arrowstyle="->", color="0.4", lw=0.8))
        ax.text(origin[0] + 1.15 * dx, origin[1] + 1.15 * dy, label, fontsize=6, color="0.3",
                ha="center", va="center")


def fig_graph(f, out, run_index, threshold, prefix):
    run = run_group(f, "khepera", run_index, configuration=CONFIGURATION)
    prototypes = run["som/prototypes"][:]
    occupied = run["graph/occupied"][:] > 0
    coords, explained, loadings = pca_layout(prototypes, occupied)
    i, j, w, total = graph_edges(run, threshold)
    fig, ax = plt.subplots(figsize=(8, 7))
    ax.add_collection(LineCollection(np.stack([coords[i], coords[j]], axis=1), colors="0.55",
                                     linewidths=0.5, alpha=0.6, zorder=1))
    # Colour: the unit's strongest reading (how close the robot is to something).
    strength = prototypes.max(axis=1)
    sc = ax.scatter(coords[occupied, 0], coords[occupied, 1], c=strength[occupied], s=14,
                    cmap="viridis", zorder=2, edgecolors="none")
    fig.colorbar(sc, ax=ax, label="largest IR reading of the unit's prototype", shrink=0.8)
    degree = np.bincount(np.concatenate([i, j]), minlength=len(prototypes))
    isolated = occupied & (degree == 0)
    if isolated.any():
        ax.scatter(coords[isolated, 0], coords[isolated, 1], s=30, facecolors="none",
                   edgecolors="k", linewidths=0.7, zorder=3,
                   label=f"no edge under {threshold:g} ({int(isolated.sum())} units)")
        ax.legend(loc="upper right", fontsize=8)
    draw_loadings(ax, coords[occupied], loadings)
    ax.set_xlabel(f"principal component 1 ({100 * explained[0]:.0f} % of variance)")
    ax.set_ylabel(f"principal component 2 ({100 * explained[1]:.0f} % of variance)")
    ax.set_title(f"SOM graph, run {run_index}: {int(occupied.sum())} occupied units, "
                 f"{len(w)} of {total} edges with weight < {threshold:g}")
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    fig.tight_layout()
    save(fig, out, f"{prefix}_graph", FORMAT, dpi=120)
    plt.close(fig)


def fig_policies(f, out, run_index, kernels, solver, prefix):
    # Layout: the SOM's own grid (top row), not the PCA plane of Fig. 4(b). In the
    # PCA plane the many units of the open floor (readings near 0) and of each wall
    # side fall on top of one another, so their arrows overprint and cannot be
    # read; on the grid every unit has its own cell, neighbouring units have
    # similar readings (the SOM's topology), and the regions of one action show as
    # patches. The bottom row colours the units by action in the PCA plane of
    # Fig. 4(b), to tie those patches to the regions of the graph.
    run = run_group(f, "khepera", run_index, configuration=CONFIGURATION)
    grid = run["som/grid"][:].astype(int)
    prototypes = run["som/prototypes"][:]
    occupied = run["graph/occupied"][:] > 0
    coords, explained, _ = pca_layout(prototypes, occupied)
    rows, cols = int(grid[:, 0].max()) + 1, int(grid[:, 1].max()) + 1
    cell = 0.26  # inches per SOM unit
    panel_w, panel_h = max(5.0, cols * cell), max(3.5, rows * cell)
    fig = plt.figure(figsize=(2 * panel_w + 1.2, panel_h + 0.75 * panel_w + 1.6),
                     layout="constrained")
    # A third, thin row holds the legend (matplotlib 3.6 has no "outside" legends).
    spec = fig.add_gridspec(3, 2, height_ratios=(panel_h, 0.75 * panel_w, 0.25))
    axes = np.array([[fig.add_subplot(spec[r, c]) for c in range(2)] for r in range(2)])
    legend_ax = fig.add_subplot(spec[2, :])
    legend_ax.axis("off")
    fontsize = max(5.0, min(14.0, 72 * cell * 0.8))
    policies = {}
    for column, basis in enumerate(("ggk", "ogk")):
        ax = axes[0, column]
        fit = fit_group(run, basis, kernels, solver)
        policy = fit["unit_policy"][:].astype(int)
        policies[basis] = policy
        centers = fit["centers"][:]
        for r, c in grid[centers]:
            ax.add_patch(patches.Rectangle((c - 0.5, r - 0.5), 1, 1, facecolor="0.85",
                                           edgecolor="none", zorder=0))
        for u, (r, c) in enumerate(grid):
            symbol, _, color = ACTIONS[policy[u]]
            ax.text(c, r, symbol, ha="center", va="center", fontsize=fontsize,
                    color=color if occupied[u] else "0.75", fontweight="bold")
        ax.set_xlim(-0.5, cols - 0.5)
        ax.set_ylim(rows - 0.5, -0.5)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_xlabel(f"SOM grid ({rows} x {cols} units)")
        counts = np.bincount(policy[occupied], minlength=4)
        ax.set_title(f"{BASIS_STYLE[basis][2]}, {kernels} kernels, {solver.upper()}: mean return "
                     f"{fit.attrs['mean_return']:.1f}\n"
                     + ",  ".join(f"{ACTIONS[a][0]} {counts[a]}" for a in range(4))
                     + " units", fontsize=10)
        ax = axes[1, column]
        order = np.argsort(policy != 0, kind="stable")  # rarer actions drawn on top
        order = order[occupied[order]]
        ax.scatter(coords[order, 0], coords[order, 1], s=10, edgecolors="none",
                   c=[ACTIONS[a][2] for a in policy[order]])
        ax.scatter(coords[centers, 0], coords[centers, 1], s=40, facecolors="none",
                   edgecolors="k", linewidths=0.6)
        ax.set_xlabel(f"PC 1 ({100 * explained[0]:.0f} %)")
        ax.set_ylabel(f"PC 2 ({100 * explained[1]:.0f} %)")
        ax.set_title("the same units in the PCA plane of Fig. 4(b)", fontsize=9)
        ax.set_aspect("equal")
    differ = int(np.sum((policies["ggk"] != policies["ogk"]) & occupied))
    handles = [Line2D([], [], linestyle="none", marker=f"${s}$", markersize=11, color=c,
                      label=name) for s, name, c in ACTIONS]
    handles.append(patches.Patch(facecolor="0.85", label="kernel centre (grid)"))
    handles.append(Line2D([], [], linestyle="none", marker="o", markerfacecolor="none",
                          markeredgecolor="k", label="kernel centre (PCA)"))
    if not occupied.all():
        handles.append(Line2D([], [], linestyle="none", marker="$\u2191$", color="0.75",
                              label="unit without samples"))
    legend_ax.legend(handles=handles, loc="center", ncol=len(handles), fontsize=9,
                     frameon=False)
    fig.suptitle(f"greedy action per SOM unit, run {run_index}: GGK and OGK differ at "
                 f"{differ} of {int(occupied.sum())} units")
    save(fig, out, f"{prefix}_policies", FORMAT, dpi=110)
    plt.close(fig)


def fig_return(summary, out, test_max_steps, prefix, job):
    runs = len(set(summary["run"]))
    # A row of panels per value of every other swept axis (sigma, lambda, a
    # study's): no axis is pooled; solvers are told apart by line style, and
    # plot_metric dodges the curves so that none hides another.
    hue = ("basis", "solver")
    rows = metric_panels(summary, hue=hue)
    fig, axes = plt.subplots(len(rows), 2, figsize=(11, 4.8 * len(rows)), squeeze=False)
    panels = (("mean_return", f"mean evaluation return (at most {test_max_steps})"),
              ("collision_fraction", "episodes stopped by a collision (%)"))
    for column, (metric, label) in enumerate(panels):
        # The whole range a value can take (a return from a collision at the
        # first step to test_max_steps forward moves, a percentage), widened to
        # every interval, so that an effect reads at its size.
        plot_metric(summary, metric, hue=hue, axes=axes[:, column], ylabel=label,
                    value_range=metric_range(metric, "khepera", job))
    fig.suptitle(f"Khepera, {runs} runs, {test_max_steps} greedy steps from the start pose "
                 f"(+1 forward, -2 collision), 95 % CI")
    fig.tight_layout()
    saved = save(fig, out, f"{prefix}_return", FORMAT, dpi=120)
    plt.close(fig)
    return saved


def draw_arena(ax, arena):
    lo, hi = arena["min"], arena["max"]
    solid = dict(facecolor="0.55", edgecolor="0.3", linewidth=0.8, zorder=1)
    if arena.get("walled", True):
        ax.add_patch(patches.Rectangle(lo, hi[0] - lo[0], hi[1] - lo[1], fill=False,
                                       edgecolor="k", linewidth=2.5, zorder=1))
    else:
        ax.add_patch(patches.Rectangle(lo, hi[0] - lo[0], hi[1] - lo[1], fill=False,
                                       edgecolor="0.6", linewidth=0.8, linestyle="--"))
    for o in arena.get("obstacles", []):
        kind = o["kind"]
        if kind == "rectangle":
            ax.add_patch(patches.Rectangle(o["min"], o["max"][0] - o["min"][0],
                                           o["max"][1] - o["min"][1], **solid))
        elif kind == "rotated_rectangle":
            (cx, cy), (w, h) = o["center"], o["size"]
            angle = o.get("angle_deg", 0.0)
            t = math.radians(angle)
            # The lower-left corner before the turn, turned about the centre.
            corner = (cx - (w * math.cos(t) - h * math.sin(t)) / 2,
                      cy - (w * math.sin(t) + h * math.cos(t)) / 2)
            ax.add_patch(patches.Rectangle(corner, w, h, angle=angle, **solid))
        elif kind == "disc":
            ax.add_patch(patches.Circle(o["center"], o["radius"], **solid))
        elif kind == "segment":
            (ax_, ay), (bx, by) = o["a"], o["b"]
            ax.plot([ax_, bx], [ay, by], color="0.3", linewidth=2.5, solid_capstyle="butt",
                    zorder=1)
        else:
            print(f"warning: obstacle kind {kind!r} not drawn", file=sys.stderr)
    margin = 2
    ax.set_xlim(lo[0] - margin, hi[0] + margin)
    ax.set_ylim(lo[1] - margin, hi[1] + margin)
    ax.set_aspect("equal")


def step_actions(trajectory):
    """The action of each step, read off the poses: a turn of more than 5 degrees is
    a rotation (left if counter-clockwise), otherwise the sign of the move along
    the heading tells forward from backward; a step that left the pose unchanged
    was undone by a collision (-1)."""
    d = np.diff(trajectory, axis=0)
    turn = (d[:, 2] + np.pi) % (2 * np.pi) - np.pi
    along = d[:, 0] * np.cos(trajectory[:-1, 2]) + d[:, 1] * np.sin(trajectory[:-1, 2])
    actions = np.where(along >= 0, 0, 3)
    actions = np.where(np.abs(turn) > math.radians(5), np.where(turn > 0, 1, 2), actions)
    still = (np.abs(turn) < 1e-12) & (np.hypot(d[:, 0], d[:, 1]) < 1e-12)
    return np.where(still, -1, actions)


def fig_trajectories(f, out, run_index, kernels, solver, arena, radius, test_max_steps, prefix):
    run = run_group(f, "khepera", run_index, configuration=CONFIGURATION)
    fig = plt.figure(figsize=(13, 7.2), layout="constrained")
    spec = fig.add_gridspec(2, 2, height_ratios=(1, 0.05))
    axes = [fig.add_subplot(spec[0, c]) for c in range(2)]
    legend_ax = fig.add_subplot(spec[1, :])
    legend_ax.axis("off")
    for ax, basis in zip(axes, ("ggk", "ogk")):
        fit = fit_group(run, basis, kernels, solver)
        draw_arena(ax, arena)
        evaluation = fit["evaluation"]
        names = sorted((n for n in evaluation if n.startswith("trajectory_")),
                       key=lambda n: int(n.split("_")[1]))
        returns = evaluation["returns"][:]
        colors = plt.get_cmap("tab10" if len(names) <= 10 else "viridis")(
            np.linspace(0, 1, len(names)) if len(names) > 10 else np.arange(len(names)))
        collisions = 0
        counts = np.zeros(4, dtype=int)
        for e, name in enumerate(names):
            t = evaluation[name][:]
            actions = step_actions(t)
            counts += np.bincount(actions[actions >= 0], minlength=4)
            ax.plot(t[:, 0], t[:, 1], "-", color=colors[e], linewidth=1.0, alpha=0.8, zorder=3)
            end = t[-1]
            # A robot disc at the final pose; a cross where a collision stopped it.
            ax.add_patch(patches.Circle(end[:2], radius, facecolor="none", edgecolor=colors[e],
                                        linewidth=0.8, zorder=3))
            if len(t) - 1 < test_max_steps:
                collisions += 1
                ax.plot(end[0], end[1], "x", color="crimson", markersize=9, mew=2.2, zorder=5)
        start = evaluation[names[0]][0]
        ax.add_patch(patches.Circle(start[:2], radius, facecolor="white", edgecolor="k",
                                    linewidth=1.2, zorder=4))
        ax.annotate("", xy=(start[0] + 2.2 * radius * math.cos(start[2]),
                            start[1] + 2.2 * radius * math.sin(start[2])),
                    xytext=start[:2], arrowprops=dict(arrowstyle="->", color="k", lw=1.5),
                    zorder=5)
        ax.set_title(f"{BASIS_STYLE[basis][2]}, {kernels} kernels, {solver.upper()}, "
                     f"run {run_index}\n"
                     f"{len(names)} episodes, mean return {returns.mean():.1f}, "
                     f"{collisions} stopped by a collision\nsteps taken: "
                     + ",  ".join(f"{ACTIONS[a][0]} {counts[a]}" for a in range(4)),
                     fontsize=10)
        ax.set_xlabel("x (cm)")
        ax.set_ylabel("y (cm)")
    handles = [Line2D([], [], marker="o", markerfacecolor="white", markeredgecolor="k",
                      linestyle="none", markersize=9, label="start pose (arrow: heading)"),
               Line2D([], [], marker="o", markerfacecolor="none", markeredgecolor="0.4",
                      linestyle="none", markersize=9, label="final pose (body)"),
               Line2D([], [], marker="x", color="crimson", mew=2.2, linestyle="none",
                      markersize=9, label="stopped by a collision"),
               patches.Patch(facecolor="0.55", edgecolor="0.3", label="obstacle")]
    legend_ax.legend(handles=handles, loc="center", ncol=4, fontsize=9, frameon=False)
    fig.suptitle(f"evaluation trajectories ({test_max_steps} greedy steps at most), "
                 "one colour per episode; actions of the steps read off the poses")
    save(fig, out, f"{prefix}_trajectories", FORMAT, dpi=120)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("out_dir")
    parser.add_argument("--kernels", type=int, default=None,
                        help="kernel count of Fig. 5 and the trajectories "
                             "(default: 100 if swept, else the largest swept)")
    parser.add_argument("--run", type=int, default=0,
                        help="run shown in Figs. 4(b), 5 and the trajectories")
    parser.add_argument("--edge-threshold", type=float, default=250.0,
                        help="draw only graph edges lighter than this (paper: 250)")
    parser.add_argument("--arena", default=None,
                        help="arena TOML to draw instead of the job's")
    parser.add_argument("--solver", default=None,
                        help="solver of Fig. 5 and the trajectories (default: brm if swept)")
    parser.add_argument("--where", action="append", default=[], metavar="KEY=VALUE",
                        help="a study's file: the run configuration with these values of its "
                             "axes (e.g. --where khepera.motion.turn_deg=45; repeatable)")
    parser.add_argument("--prefix", default="khepera",
                        help="file names PREFIX_graph.png, ... (default: khepera)")
    add_format_argument(parser)
    args = parser.parse_args()
    global FORMAT, CONFIGURATION
    FORMAT = args.format
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary, CONFIGURATION = select_where(read_summary(args.results, "khepera"), args.where)
    kernels = args.kernels
    if kernels is None:
        swept = set(int(k) for k in summary["kernels"])
        kernels = 100 if 100 in swept else max(swept)
    solver = args.solver
    if solver is None:
        swept = sorted(set(summary["solver"]))
        solver = "brm" if "brm" in swept else swept[0]
    with h5py.File(args.results, "r") as f:
        khepera = job_config(f).get("khepera", {})
        test_max_steps = int(khepera.get("test_max_steps", 150))
        radius = float(khepera.get("robot", {}).get("radius", 2.6))
        arena = read_arena(f, args.results, args.arena)
        fig_graph(f, out, args.run, args.edge_threshold, args.prefix)
        fig_policies(f, out, args.run, kernels, solver, args.prefix)
        fig_trajectories(f, out, args.run, kernels, solver, arena, radius, test_max_steps,
                         args.prefix)
    # The file's resolved job names every setting; a file older than it, the job's.
    job = job_settings(args.results) or {"khepera.test_max_steps": test_max_steps}
    fig_return(summary, out, test_max_steps, args.prefix, job)
    for name in ("graph", "policies", "return", "trajectories"):
        print(out / f"{args.prefix}_{name}.{args.format}")


if __name__ == "__main__":
    main()
