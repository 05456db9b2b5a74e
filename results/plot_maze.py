"""Success rate vs number of kernels on the maze, GGK vs OGK (and PVF where run), 95 % CIs over runs
(Student t): one panel per value of every other swept axis (solver, sigma,
lambda), so that no axis is pooled.

    /usr/bin/python3 results/plot_maze.py results/maze.h5 results/figures [--format pdf]
"""

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import (add_format_argument, curve, error_bars, facet_title, facets,  # noqa: E402
                         legend_below, read_summary, save)

STYLE = {"ggk": ("tab:red", "o", "geodesic (GGK)"), "ogk": ("tab:blue", "s", "ordinary (OGK)"),
         "pvf": ("tab:green", "^", "proto-value functions (PVF)")}
# The curves' bases, in drawing order; a basis the file lacks draws no curve.
CURVE_BASES = ("ggk", "ogk", "pvf")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("out_dir")
    add_format_argument(parser)
    args = parser.parse_args()
    summary = read_summary(args.results, "maze")
    out_dir = Path(args.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    panels = facets(summary, shown=("kernels", "basis"))
    columns = min(3, len(panels))
    rows = (len(panels) + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, figsize=(5.5 * columns, 4 * rows), squeeze=False)
    runs = len(set(summary["run"]))
    for ax, panel in zip(axes.flat, panels):
        for basis in CURVE_BASES:
            k, est, low, high = curve(summary, "success_rate", basis=basis, **panel)
            if len(k) == 0:
                continue
            color, marker, label = STYLE[basis]
            ax.errorbar(k, 100 * est, yerr=100 * error_bars(est, low, high), color=color,
                        marker=marker, capsize=3, label=label)
        ax.set_title(f"maze, {facet_title(panel) or 'LSPI'}, {runs} runs, 95 % CI", fontsize=10)
        ax.set_xlabel("number of kernels")
        ax.set_ylabel("success rate from all cells (%)")
        ax.set_ylim(0, 100)  # a rate: the whole range, so differences read at their size
        ax.grid(alpha=0.3)
        legend_below(ax)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    fig.tight_layout()
    print(save(fig, out_dir, "maze_success", args.format))


if __name__ == "__main__":
    main()
