"""Success rate vs number of kernels on the maze, GGK vs OGK, 95 % CIs over runs.

    /usr/bin/python3 results/plot_maze.py results/maze.h5 results/figures
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ggk_results import curve, read_summary  # noqa: E402

STYLE = {"ggk": ("tab:red", "o", "geodesic (GGK)"), "ogk": ("tab:blue", "s", "ordinary (OGK)")}


def main(results, out_dir):
    summary = read_summary(results, "maze")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    solvers = sorted(set(summary["solver"]))
    fig, axes = plt.subplots(1, len(solvers), figsize=(5.5 * len(solvers), 4), squeeze=False)
    for ax, solver in zip(axes[0], solvers):
        for basis in ("ggk", "ogk"):
            k, mean, half = curve(summary, "success_rate", basis=basis, solver=solver)
            color, marker, label = STYLE[basis]
            ax.errorbar(k, 100 * mean, yerr=100 * half, color=color, marker=marker, capsize=3,
                        label=label)
        runs = len(set(summary["run"]))
        ax.set_title(f"maze, LSPI ({solver.upper()}), {runs} runs, 95 % CI")
        ax.set_xlabel("number of kernels")
        ax.set_ylabel("success rate from all cells (%)")
        ax.set_ylim(0, 100)
        ax.grid(alpha=0.3)
        ax.legend()
    fig.tight_layout()
    path = out_dir / "maze_success.png"
    fig.savefig(path, dpi=120)
    print(path)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
