"""LSPI's stopping rules, measured (issue 11 item 4), from a results file made with
[lspi] evaluate_iterations = true (every iteration's weights and test stored):

  <stem>_swing.png        the metric vs kernels: the stored (cap) iterate and
                          the band its policy swings through over the last 10
                          iterations
  <stem>_iterations.png   the test metric of every iteration's greedy policy
                          (arm: success from A; khepera: mean return), mean over
                          runs, one panel per (solver, kernel count), GGK vs OGK
  stdout                  per (solver, basis, kernels): how the fits stop under
                          each rule, and the metric each rule's policy gets

    /usr/bin/python3 results/plot_iterations.py FILE OUT_DIR [--epsilon 1e-5]
        [--metric NAME] [--format png|pdf|svg]

The two rules, both read off the same stored iterations (no rule and no
iteration is chosen by its result):
  policy   stop when the greedy action changes on no sample state
           (history/policy_changes == 0), ggk's default;
  weights  stop when ||w_k - w_(k-1)||_2 <= epsilon (history/weight_change),
           Lagoudakis & Parr's rule.
A fit that stopped by the policy rule at iteration k has the same weights at
k + 1 (the same policy gives the same system), so the weights rule would stop
there with the same policy: its stopping point and metric are exact from a file
run under either rule, up to the max_iterations cap of the job. A fit still
changing at the cap ends on the cap's iterate under both rules; such a fit is
`cycling` with period q when its last weights repeat those of q iterations
before within 1e-9 relative (q = 2: two policies alternate), q <= 16.
"""

import argparse
import sys
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import add_format_argument, save, task_of  # noqa: E402

STYLE = {"ggk": ("tab:red", "-", "geodesic (GGK)"), "ogk": ("tab:blue", "--", "ordinary (OGK)"),
         "pvf": ("tab:green", ":", "proto-value functions (PVF)")}
BASES = ("ggk", "ogk", "pvf")  # a basis the file lacks shows nothing
TAIL = 10  # the last iterations whose range shows a cycle's swing
DEFAULT_METRIC = {"arm": "success_from_A", "maze": "success_rate", "khepera": "mean_return"}


def read_fits(path, metric):
    """One dict per fit with its axis values, status, and history arrays."""
    fits = []
    with h5py.File(path, "r") as f:
        task = task_of(path)
        max_iterations = None
        for run_name in sorted(f[task]):
            if not run_name.startswith("run_"):
                continue
            root = f[task][run_name]["fits"]
            for basis in sorted(root):
                for name in sorted(root[basis]):
                    g = root[basis][name]
                    h = g.get("history")
                    if h is None or "weights" not in h:
                        if g.attrs["status"] in ("invalid", "solver_failed"):
                            continue
                        raise SystemExit(f"{path}: {g.name} has no history/weights: run the job "
                                         "with --set lspi.evaluate_iterations=true")
                    fits.append({
                        "run": int(run_name[4:]),
                        "basis": basis,
                        "kernels": int(g.attrs["kernels"]),
                        "solver": str(g.attrs["solver"]),
                        "status": str(g.attrs["status"]),
                        "policy_changes": h["policy_changes"][:],
                        "weight_change": h["weight_change"][:],
                        "weights": h["weights"][:],
                        "metric": h[metric][:],
                    })
        import tomllib  # the job's max_iterations: the cap both rules share
        job = tomllib.loads(f.attrs["job"] if isinstance(f.attrs["job"], str)
                            else f.attrs["job"].decode())
        max_iterations = job.get("lspi", {}).get("max_iterations", 20)
    return task, fits, max_iterations


def stopping_points(fit, epsilon, cap):
    """((iteration, stopped) of the policy rule, the same of the weights rule,
    cycle period or 0), iterations 1-based; `stopped` False means the rule never
    held before the cap (the fit ends on the cap's iterate). The period is the
    smallest q <= 16 with w_n = w_(n-q) within 1e-9 relative, for a fit the policy
    rule did not stop (q = 2: two policies alternate)."""
    changes, moved = fit["policy_changes"], fit["weight_change"]
    n = len(changes)
    by_policy = next((i + 1 for i in range(n) if changes[i] == 0), None)
    by_weights = next((i + 1 for i in range(n) if moved[i] <= epsilon), None)
    if by_weights is None and by_policy is not None and by_policy < cap:
        by_weights = by_policy + 1  # the next evaluation repeats w exactly
    period = 0
    if by_policy is None:
        w = fit["weights"]
        scale = max(1.0, np.linalg.norm(w[-1]))
        period = next((q for q in range(1, 17)
                       if n > q and np.linalg.norm(w[-1] - w[-1 - q]) <= 1e-9 * scale), 0)
    return ((by_policy or n, by_policy is not None), (by_weights or n, by_weights is not None),
            period)


def metric_at(fit, iteration):
    series = fit["metric"]
    return series[min(iteration, len(series)) - 1]


def padded(series, length):
    """A fit's per-iteration series carried to `length` iterations: after the
    policy rule stopped, the policy (and its test) no longer changes."""
    out = np.full(length, series[-1], dtype=float)
    out[:len(series)] = series
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results")
    parser.add_argument("out_dir")
    parser.add_argument("--epsilon", type=float, default=1e-5,
                        help="epsilon of the weights rule (default 1e-5, lspi-python's default)")
    parser.add_argument("--metric", help="history metric (default: success_from_A for the arm, "
                        "success_rate for the maze, mean_return for the khepera)")
    add_format_argument(parser)
    args = parser.parse_args()

    task = task_of(args.results)
    metric = args.metric or DEFAULT_METRIC[task]
    task, fits, cap = read_fits(args.results, metric)
    if not fits:
        raise SystemExit(f"{args.results}: no fits with stored iterations")
    solvers = sorted({f["solver"] for f in fits})
    counts = sorted({f["kernels"] for f in fits})

    print(f"{args.results}: {len(fits)} fits, metric {metric}, cap {cap} iterations, "
          f"weights rule epsilon {args.epsilon:g}")
    print("solver basis kernels | fits | policy rule: stopped, mean it, metric | "
          "weights rule: stopped, mean it, metric | at the cap: cycles (count x period), "
          f"other | metric min..max over the last {TAIL} it, mean over fits")
    for solver in solvers:
        for k in counts:
            for basis in BASES:
                group = [f for f in fits if f["solver"] == solver and f["basis"] == basis
                         and f["kernels"] == k]
                if not group:
                    continue
                points = [stopping_points(f, args.epsilon, cap) for f in group]
                stopped_p = sum(p[0][1] for p in points)
                stopped_w = sum(p[1][1] for p in points)
                m_p = np.mean([metric_at(f, p[0][0]) for f, p in zip(group, points)])
                m_w = np.mean([metric_at(f, p[1][0]) for f, p in zip(group, points)])
                it_p = np.mean([p[0][0] for p in points])
                it_w = np.mean([p[1][0] for p in points])
                periods = [p[2] for p in points if not p[0][1]]
                cycling = " ".join(f"{periods.count(q)}x{q}" for q in range(1, 17)
                                   if periods.count(q)) or "-"
                drifting = sum(q == 0 for q in periods)
                tails = [padded(f["metric"], cap)[-TAIL:] for f in group]
                low = np.mean([t.min() for t in tails])
                high = np.mean([t.max() for t in tails])
                print(f"{solver:5s} {basis} {k:4d} | {len(group):3d} | {stopped_p:3d} {it_p:5.1f} "
                      f"{m_p:7.3f} | {stopped_w:3d} {it_w:5.1f} {m_w:7.3f} | {cycling:>14s} "
                      f"{drifting:3d} | "
                      f"{low:.3f}..{high:.3f}")

    fig, axes = plt.subplots(len(solvers), len(counts), sharex=True, sharey=True,
                             figsize=(2.2 * len(counts) + 1, 2.4 * len(solvers) + 0.8),
                             squeeze=False)
    for r, solver in enumerate(solvers):
        for c, k in enumerate(counts):
            ax = axes[r][c]
            for basis in BASES:
                group = [f for f in fits if f["solver"] == solver and f["basis"] == basis
                         and f["kernels"] == k]
                if not group:
                    continue
                curves = np.array([padded(f["metric"], cap) for f in group])
                color, style, label = STYLE[basis]
                ax.plot(np.arange(1, cap + 1), np.nanmean(curves, axis=0), style, color=color,
                        label=label)
            ax.set_title(f"{solver}, {k} kernels", fontsize=9)
            if r == len(solvers) - 1:
                ax.set_xlabel("LSPI iteration")
            if c == 0:
                ax.set_ylabel(metric)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(handles), frameon=False)
    fig.suptitle(f"{task}: every iteration's greedy policy, mean over runs "
                 "(after the policy rule stops, the last policy repeats)", fontsize=10)
    fig.tight_layout(rect=(0, 0.06, 1, 0.95))
    stem = Path(args.results).stem
    print(save(fig, args.out_dir, f"{stem}_iterations", args.format))

    # The metric vs kernels: the cap's iterate (what the fit stores) and the range
    # its policy swings through over the last TAIL iterations (mean over runs of
    # each run's min and max): a cycle's phase at the cap decides the stored value.
    fig, axes = plt.subplots(1, len(solvers), figsize=(5 * len(solvers), 3.6), squeeze=False)
    for c, solver in enumerate(solvers):
        ax = axes[0][c]
        for basis in BASES:
            finals, lows, highs, shown = [], [], [], []
            for k in counts:
                group = [f for f in fits if f["solver"] == solver and f["basis"] == basis
                         and f["kernels"] == k]
                if not group:
                    continue
                tails = np.array([padded(f["metric"], cap)[-TAIL:] for f in group])
                shown.append(k)
                finals.append(np.mean(tails[:, -1]))
                lows.append(np.mean(tails.min(axis=1)))
                highs.append(np.mean(tails.max(axis=1)))
            color, style, label = STYLE[basis]
            ax.fill_between(shown, lows, highs, color=color, alpha=0.2, linewidth=0)
            ax.plot(shown, finals, style, color=color, marker="o",
                    label=f"{label}: iteration {cap} (stored)")
        ax.set_xlabel("number of kernels")
        ax.set_ylabel(metric)
        ax.set_title(f"{solver}: band = mean min..max over the last {TAIL} iterations",
                     fontsize=9)
        ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    print(save(fig, args.out_dir, f"{stem}_swing", args.format))


if __name__ == "__main__":
    main()
